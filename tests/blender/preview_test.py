"""Tests of `shellfrac preview` and of apps/shellfrac/blender/count_loose_parts.py.

    python3 preview_test.py render  --shellfrac BIN --out DIR [--blender B]
    python3 preview_test.py errors  --shellfrac BIN --out DIR
    python3 preview_test.py parts   --shellfrac BIN --out DIR [--blender B]
    python3 preview_test.py formats --shellfrac BIN --out DIR [--blender B]
"""
import argparse
import json
import math
import os
import shutil

import blender_tools as bt
import png_reader

SCENES = os.path.join(bt.HERE, "scenes")
BACKDROP = (53, 57, 64)  # the camera's backdrop, linear 0.035/0.04/0.05 through the sRGB curve


def obj_vertices(path):
    """'v' lines of an OBJ file, in Blender's frame (the importer maps OBJ's Y-up (x, y, z) to (x, -z, y))."""
    out = []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                x, y, z = map(float, line.split()[1:4])
                out.append((x, -z, y))
    return out


def project(camera, p, width, height):
    """Pinhole projection with Blender's conventions: the camera looks down its -Z, sensor fit horizontal."""
    r, c = camera["matrix"], camera["location"]  # r: rows of the camera-to-world rotation
    d = [p[i] - c[i] for i in range(3)]
    q = [sum(r[i][k] * d[i] for i in range(3)) for k in range(3)]  # R^T d
    f = camera["lens"] / camera["sensor_width"] * width  # focal length in pixels
    return (width / 2 + f * q[0] / -q[2], height / 2 - f * q[1] / -q[2])


def hull_area(points):
    pts = sorted(set(points))
    if len(pts) < 3:
        return 0.0

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower, upper = [], []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    for p in reversed(pts):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    hull = lower[:-1] + upper[:-1]
    return 0.5 * abs(sum(hull[i][0] * hull[i - 1][1] - hull[i - 1][0] * hull[i][1] for i in range(len(hull))))


def test_render(args):
    blender = bt.blender_program(args.blender)
    run_dir = os.path.join(args.out, "tiny-sheet")
    summary = bt.shellfrac_run(args.shellfrac, os.path.join(SCENES, "tiny-sheet.json"), run_dir, threads=1)
    bt.check(len(summary["frames"]) == 2, "the tiny scene should write 2 frames, wrote %d" % len(summary["frames"]))
    png_dir = os.path.join(args.out, "tiny-sheet-png")
    shutil.rmtree(png_dir, ignore_errors=True)
    width, height = 200, 150
    env = dict(os.environ, SHELLFRAC_BLENDER=blender)
    # A copy of the binary in a folder of its own: the Blender scripts travel inside it.
    relocated = os.path.join(args.out, "relocated", "bin", "shellfrac")
    os.makedirs(os.path.dirname(relocated), exist_ok=True)
    shutil.copy2(args.shellfrac, relocated)
    code, out, err = bt.run([relocated, "preview", run_dir, "--frames", "all", "--size", "%dx%d" % (width, height),
                             "--samples", "4", "--threads", "2", "--out", png_dir], env=env)
    bt.check(code == 0, "preview exited %d:\n%s%s" % (code, out, err))
    with open(os.path.join(png_dir, "preview.json")) as f:
        record = json.load(f)
    for k in (0, 1):
        png = os.path.join(png_dir, "frame_%05d.png" % k)
        bt.check(os.path.isfile(png), "no %s" % png)
        w, h, px = png_reader.pixels(png)
        bt.check((w, h) == (width, height), "%s is %dx%d, asked for %dx%d" % (png, w, h, width, height))
        distinct = len(set(px))
        bt.check(distinct > 50, "%s has only %d distinct colours: a blank render?" % (png, distinct))
        covered = sum(1 for p in px if max(abs(p[i] - BACKDROP[i]) for i in range(3)) > 8) / len(px)
        # Independent prediction: the flat sheet's outline is the convex hull of its projected vertices.
        verts = obj_vertices(os.path.join(run_dir, summary["frames"][k]))
        predicted = hull_area([project(record["camera"], v, width, height) for v in verts]) / (width * height)
        print("frame %d: %d distinct colours, mesh covers %.4f of the image, the projected sheet %.4f"
              % (k, distinct, covered, predicted))
        # Antialiased outline pixels are half covered: about perimeter / 2 pixels, ~1% of this image.
        bt.check(abs(covered - predicted) < 0.02,
                 "%s: the mesh covers %.4f of the image, the camera projects the sheet onto %.4f" % (png, covered, predicted))
        bt.check(predicted > 0.3, "the camera should frame the sheet, not leave it small (%.3f)" % predicted)
        fr = record["frames"][k]
        bt.check(fr["loose_parts"] == 1 and fr["slivers"] == 0 and fr["strand_faces"] == 0,
                 "frame %d: an intact sheet is one part without slivers or strands: %s" % (k, fr))
    # Frame 0 is the rest state itself: every edge has stretch 1 (up to float32 vertex coordinates).
    bt.check(record["frames"][0]["stretch_reference"] == "rest", "stretch not measured against frame 0: %s" % record["frames"][0])
    bt.check(abs(record["frames"][0]["max_edge_stretch"] - 1) < 1e-5,
             "frame 0 measured against itself should have stretch 1, got %r" % record["frames"][0]["max_edge_stretch"])
    # Contact sheet: thumbnails 200 px wide (the images are narrower than 240), 2 in a row, 6 px gaps,
    # a 22 px label strip under each.
    w, h, px = png_reader.pixels(os.path.join(png_dir, "contact_sheet.png"))
    bt.check((w, h) == (2 * (width + 6) + 6, height + 22 + 6 + 6), "contact sheet is %dx%d" % (w, h))
    bt.check(len(set(px)) > 50, "the contact sheet looks blank")
    print("render seconds per frame (200x150, 4 samples): %.2f" % record["render_seconds_per_frame"])


def test_errors(args):
    run_dir = os.path.join(args.out, "tiny-sheet-errors")
    bt.shellfrac_run(args.shellfrac, os.path.join(SCENES, "tiny-sheet.json"), run_dir, threads=1)
    missing = os.path.join(args.out, "no-such-blender")
    env = dict(os.environ, SHELLFRAC_BLENDER=missing)
    code, out, err = bt.run([args.shellfrac, "preview", run_dir], env=env)
    bt.check(code == 1, "SHELLFRAC_BLENDER pointing to a missing file: exit %d, expected 1" % code)
    for needle in ("SHELLFRAC_BLENDER=" + missing, "apt-get install blender", "scripts/setup.sh"):
        bt.check(needle in err, "the message should say %r:\n%s" % (needle, err))
    env = {k: v for k, v in os.environ.items() if k != "SHELLFRAC_BLENDER"}
    env["PATH"] = os.path.join(args.out, "empty-path")
    code, out, err = bt.run([args.shellfrac, "preview", run_dir], env=env)
    bt.check(code == 1 and "not on PATH" in err and "apt-get install blender" in err,
             "no blender on PATH: exit %d, expected 1 with a message:\n%s" % (code, err))
    # Bad input is reported before Blender is looked for: exit 2 and what is wrong.
    for argv, needle in (([run_dir, "--size", "10x10"], "--size 10x10"),
                         ([run_dir, "--size", "wide"], "WIDTHxHEIGHT"),
                         ([run_dir, "--frames", "7"], "frame 7 is out of range: the run has frames 0..1"),
                         ([run_dir, "--frames", "1-0"], "is empty"),
                         ([run_dir, "--frames", "x"], "is not a frame number"),
                         ([run_dir, "--samples", "0"], "samples"),
                         ([os.path.join(args.out, "no-such-run")], "summary.json")):
        code, out, err = bt.run([args.shellfrac, "preview"] + argv, env=dict(os.environ, SHELLFRAC_BLENDER=missing))
        bt.check(code == 2 and needle in out + err, "preview %s: exit %d (expected 2) and %r in:\n%s%s"
                 % (" ".join(argv), code, needle, out, err))
    print("missing Blender: exit 1 with the install hint; bad input: exit 2")


def test_parts(args):
    """count_loose_parts.py against shapes whose part count is known without Blender."""
    blender = bt.blender_program(args.blender)
    cases = (("tiny-sheet.json", 1, 1, 1),   # an intact sheet
             ("cut-through.json", 2, 2, 2),  # a prescribed cut from border to border splits it in two
             ("two-patches.json", 2, 2, 1))  # two patches coupled C0 along a seam: 2 objects, 1 body
    for scene, objects_total, total, welded in cases:
        run_dir = os.path.join(args.out, os.path.splitext(scene)[0])
        summary = bt.shellfrac_run(args.shellfrac, os.path.join(SCENES, scene), run_dir, threads=1)
        rec = bt.count_loose_parts(blender, os.path.join(run_dir, summary["frames"][-1]))
        print("%s: %s" % (scene, json.dumps({k: rec[k] for k in ("objects", "total", "welded")})))
        bt.check(sum(rec["objects"].values()) == objects_total and rec["total"] == total and rec["welded"] == welded,
                 "%s: expected %d parts over the objects and %d welded, Blender says %s" % (scene, total, welded, rec))
        joined = bt.count_loose_parts(blender, os.path.join(run_dir, summary["frames"][-1]), ["--join"])
        bt.check(len(joined["objects"]) == 1 and joined["total"] == total,
                 "%s joined into one object (no welding): expected %d parts, got %s" % (scene, total, joined))
    # Two uncoupled OBJ patches side by side, a gap between them: Blender 3.4 imports one object (the shells
    # are vertex groups), two loose parts; the seam weld joins them when the gap is under the weld distance.
    for gap, welded in ((5e-5, 1), (1e-3, 2)):
        with open(os.path.join(SCENES, "two-patches.json")) as f:
            data = json.load(f)
        data["output"]["format"], data["gravity"] = "obj", [0, 0, 0]
        del data["interfaces"]
        data["shells"][1]["patch"]["origin"] = [0.5 + gap, 0, 0]
        scene = os.path.join(args.out, "two-patches-gap-%g.json" % gap)
        with open(scene, "w") as f:
            json.dump(data, f)
        run_dir = os.path.join(args.out, "two-patches-gap-%g" % gap)
        summary = bt.shellfrac_run(args.shellfrac, scene, run_dir, threads=1)
        rec = bt.count_loose_parts(blender, os.path.join(run_dir, summary["frames"][-1]))
        print("two patches %g m apart: %s" % (gap, json.dumps({k: rec[k] for k in ("objects", "total", "welded")})))
        bt.check(rec["total"] == 2 and rec["welded"] == welded,
                 "two patches %g m apart: expected 2 parts, %d welded (weld distance 1e-4 m): %s" % (gap, welded, rec))


def scene_in_format(scene, fmt, directory):
    """A copy of a test scene that writes its frames as `fmt` (an assimp export id)."""
    with open(os.path.join(SCENES, scene)) as f:
        data = json.load(f)
    data["output"]["format"] = fmt
    path = os.path.join(directory, "%s-%s.json" % (os.path.splitext(scene)[0], fmt))
    with open(path, "w") as f:
        json.dump(data, f)
    return path


def test_formats(args):
    """Every frame format preview reads: the cut-through sheet is 2 parts in Blender and in the preview."""
    blender = bt.blender_program(args.blender)
    env = dict(os.environ, SHELLFRAC_BLENDER=blender)
    for fmt in ("ply", "stl", "gltf2", "glb2", "collada"):
        run_dir = os.path.join(args.out, "cut-through-" + fmt)
        summary = bt.shellfrac_run(args.shellfrac, scene_in_format("cut-through.json", fmt, args.out), run_dir, threads=1)
        rec = bt.count_loose_parts(blender, os.path.join(run_dir, summary["frames"][-1]))
        bt.check(rec["welded"] == 2, "%s: the cut-through sheet should be 2 parts in Blender, got %s" % (fmt, rec))
        if fmt in ("ply", "glb2"):  # the whole command too, on a format without and one with objects per shell
            png_dir = os.path.join(run_dir, "png")
            code, out, err = bt.run([args.shellfrac, "preview", run_dir, "--size", "64x48", "--samples", "1",
                                     "--threads", "2", "--out", png_dir], env=env)
            bt.check(code == 0, "preview of the %s run exited %d:\n%s%s" % (fmt, code, out, err))
            with open(os.path.join(png_dir, "preview.json")) as f:
                frame = json.load(f)["frames"][0]
            bt.check(frame["loose_parts"] == 2, "preview of the %s run: %d loose parts, expected 2" % (fmt, frame["loose_parts"]))
            w, h, _ = png_reader.pixels(frame["png"])
            bt.check((w, h) == (64, 48), "%s: a %dx%d PNG, asked for 64x48" % (fmt, w, h))
        print("%s: 2 loose parts" % fmt)
    # A format Blender cannot read back is refused before Blender starts, with the list of those it can.
    run_dir = os.path.join(args.out, "tiny-fbx")
    bt.shellfrac_run(args.shellfrac, scene_in_format("tiny-sheet.json", "fbx", args.out), run_dir, threads=1)
    code, out, err = bt.run([args.shellfrac, "preview", run_dir], env=env)
    bt.check(code == 2 and ".obj, .ply, .stl, .gltf, .glb, .dae" in err and "not .fbx" in err,
             "preview of an FBX run: exit %d (expected 2) with the readable formats:\n%s" % (code, err))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("test", choices=("render", "errors", "parts", "formats"))
    ap.add_argument("--shellfrac", required=True)
    ap.add_argument("--blender")
    ap.add_argument("--out", required=True)
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    {"render": test_render, "errors": test_errors, "parts": test_parts, "formats": test_formats}[args.test](args)
    print("PASS")


if __name__ == "__main__":
    bt.main_guard(main)
