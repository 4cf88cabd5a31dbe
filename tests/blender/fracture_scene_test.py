"""Real-client check of a shipped fracture scene: run it, import its last frame into Blender, and
assert that Blender's loose-part count equals metrics.pieces + metrics.slivers.count; then the scene's own
fracture criteria on its summary.json (check_scene_criteria), so each scene runs once.

    python3 fracture_scene_test.py --list SCENES_DIR
        prints the fracture scenes (a shell with a "fracture" material or "cuts"), one path a line
    python3 fracture_scene_test.py --shellfrac BIN --out DIR [--blender B] [--count-only] SCENE.json...
        runs each scene at its shipped resolution with --threads 2; --count-only prints Blender's count and
        whatever summary.json has instead of asserting
"""
import argparse
import glob
import json
import math
import os
import sys
import time

import blender_tools as bt


def is_fracture_scene(path):
    with open(path) as f:
        scene = json.load(f)
    return any("fracture" in s.get("material", {}) or s.get("cuts") for s in scene.get("shells", []))


def fracture_scenes(directory):
    return [p for p in sorted(glob.glob(os.path.join(directory, "*.json"))) if is_fracture_scene(p)]


def expected_parts(summary):
    """pieces + slivers.count from summary.json, or None and the reason when the keys are missing."""
    metrics = summary.get("metrics", {})
    missing = [k for k, ok in (("metrics.pieces", isinstance(metrics.get("pieces"), int)),
                               ("metrics.slivers.count",
                                isinstance(metrics.get("slivers"), dict) and isinstance(metrics["slivers"].get("count"), int)))
               if not ok]
    if missing:
        return None, "summary.json has no %s" % " or ".join(missing)
    return metrics["pieces"] + metrics["slivers"]["count"], None


def crack_components(graph):
    """Connected components of a crack graph's edges (vertices without edges are not counted)."""
    parent = list(range(len(graph["vertices"])))

    def find(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x
    for a, b in graph["edges"]:
        parent[find(a)] = find(b)
    return len({find(a) for a, _ in graph["edges"]})


# Shipped fracture scenes that do not yet meet the clean-in-every-frame criteria (check_clean_every_frame),
# with what was measured under the default (2026-12-07: PIC where damaged, continuous supports). Their
# values are printed, not asserted; every other fracture scene must meet them.
KNOWN_UNCLEAN = {
    "rubber-notches": "a strand of 2.0e-7 m^2 in some frame (peak edge stretch 1.64)",
    "spiral-cut": "peak edge stretch 9.06 at frame 17, strand area 4.0e-6 m^2: the uncut tip of the cut, pulled by "
                  "the unwound ribbon (docs/mls.md)",
    "glass-pane-ball": "13 pieces and 2 slivers (8.5e-5 m^2) at the impact; 4 pieces and none under the rule before "
                       "(docs/shell-model.md, \"Transfer\")",
}

# Scene criteria of check_scene_criteria that the default does not yet meet: printed, not asserted.
KNOWN_CRITERIA_FAILURES = {
    ("plate-pressure", "centre"): "the four quarters of Fig. 4.19c and a central piece of 0.08 m^2: the arms end "
                                  "0.119 from the centre (2026-12-07; the sudden load, docs/shell-model.md \"Transfer\")",
}


def check_or_known(name, criterion, ok, message):
    """bt.check, unless (name, criterion) is a known failure: then the outcome is printed."""
    why = KNOWN_CRITERIA_FAILURES.get((name, criterion))
    if why is None:
        bt.check(ok, message)
    else:
        print("%s: known failure (%s): %s" % (name, why, "now met" if ok else message))


def check_clean_every_frame(name, m):
    """Clean in every frame: no render edge of any frame stretched beyond 3 (the strand threshold), no
    strand face in any frame, no slivers."""
    problems = []
    if m["peak_edge_stretch"]["value"] > 3.0:
        problems.append("peak edge stretch %.3f at frame %s, expected at most 3"
                        % (m["peak_edge_stretch"]["value"], m["peak_edge_stretch"]["frame"]))
    if m["peak_strand_area"] != 0.0:
        problems.append("strand area %g m^2 in some frame, expected 0" % m["peak_strand_area"])
    if m["slivers"]["count"] != 0:
        problems.append("%d sliver(s), expected 0" % m["slivers"]["count"])
    if name in KNOWN_UNCLEAN:
        print("%s: known failure (%s): %s" % (name, KNOWN_UNCLEAN[name], "; ".join(problems) or "now clean"))
        return
    bt.check(not problems, "%s: %s" % (name, "; ".join(problems)))


def check_scene_criteria(name, summary):
    """The per-scene fracture criteria, on the shipped scene at its shipped resolution. Every
    fracture scene: no material without a basis, the strict-subset property of the crack graph, and clean
    in every frame."""
    m = summary["metrics"]
    cracks = m["cracks"]
    bt.check(cracks["mls_failures"] == 0, "%s: mls_failures %d, expected 0" % (name, cracks["mls_failures"]))
    bt.check(cracks["subset_violations"] == 0,
             "%s: %d subset violations, expected 0" % (name, cracks["subset_violations"]))
    check_clean_every_frame(name, m)
    if name == "tear-mode-one":
        bt.check(m["pieces"] == 2 and min(m["piece_areas"]) >= 0.4,
                 "%s: pieces %d with areas %s, expected 2 of at least 0.4 m^2" % (name, m["pieces"], m["piece_areas"]))
        bt.check(m["slivers"]["count"] == 0, "%s: %s, expected no slivers" % (name, m["slivers"]))
        bt.check(0.99 <= sum(m["piece_areas"]) <= 1.01,
                 "%s: total area %.6f m^2, expected within [0.99, 1.01]" % (name, sum(m["piece_areas"])))
        # The grown crack joins the notch: the prescribed cut and the grown crack are one graph component.
        graph = summary["crack_graphs"][0]
        bt.check(crack_components(graph) == 1,
                 "%s: the crack graph has %d components: the grown crack does not join the notch"
                 % (name, crack_components(graph)))
        bt.check(m["strand_area"] == 0.0, "%s: strand area %g m^2 (%d faces), expected 0"
                 % (name, m["strand_area"], m["strand_faces"]))
    elif name == "rubber-notches":
        bt.check(m["pieces"] == 2, "%s: %d pieces, expected 2" % (name, m["pieces"]))
        bt.check(m["strand_area"] == 0.0, "%s: strand area %g m^2 (%d faces), expected 0"
                 % (name, m["strand_area"], m["strand_faces"]))
    elif name == "cloth-two-balls":
        bt.check(m["max_edge_stretch"] <= 3.0, "%s: max edge stretch %g, expected at most 3" % (name, m["max_edge_stretch"]))
    elif name == "glass-pane-ball":
        # A ball of the rigid world strikes the pane's centre (thesis Fig. 4.29): at least three pieces, and
        # cracks that start at the impact point and run out radially into all four quadrants.
        bt.check(m["pieces"] >= 3, "%s: %d pieces, expected at least 3" % (name, m["pieces"]))
        vertices = summary["crack_graphs"][0]["vertices"]
        gap = min(math.dist((0.5, 0.5), v) for v in vertices)
        bt.check(gap <= 0.05, "%s: the nearest crack vertex is %.3f from the impact point (0.5, 0.5) in the parameter "
                 "plane, expected within 0.05 (1.6 cells)" % (name, gap))
        quadrants = {(v[0] > 0.5, v[1] > 0.5) for v in vertices if math.dist((0.5, 0.5), v) > 0.2}
        bt.check(len(quadrants) == 4, "%s: cracks reach 0.2 from the impact point in %d of 4 quadrants"
                 % (name, len(quadrants)))
    elif name == "plate-pressure":
        # Run to EXTENDED_END[name] (three times the shipped end): four cracks from the centre to the corners
        # (thesis Fig. 4.19c) cut the plate into four large pieces, and the run does not diverge.
        big = [a for a in m["piece_areas"] if a >= 0.2]
        bt.check(len(big) >= 4, "%s: pieces of at least 0.2 m^2: %s, expected 4" % (name, m["piece_areas"]))
        vertices = summary["crack_graphs"][0]["vertices"]
        for corner in ((0.5, 0.5), (0, 0), (1, 0), (0, 1), (1, 1)):
            gap = min(math.dist(corner, v) for v in vertices)
            check_or_known(name, "centre" if corner == (0.5, 0.5) else "corners", gap <= 0.1,
                           "%s: the nearest crack vertex is %.3f from (%g, %g) in the parameter plane, "
                           "expected within 0.1 (2.4 cells)" % (name, gap, corner[0], corner[1]))


# Scenes run past their shipped end, to show that they stay stable where the crack keeps growing.
EXTENDED_END = {"plate-pressure": 0.45}


def scene_to_run(scene, name, copy_dir):
    """The shipped scene, or a copy in copy_dir with time.end from EXTENDED_END."""
    if name not in EXTENDED_END:
        return scene
    with open(scene) as f:
        data = json.load(f)
    data["time"]["end"] = EXTENDED_END[name]
    os.makedirs(copy_dir, exist_ok=True)
    copy = os.path.join(copy_dir, "%s-to-%gs.json" % (name, EXTENDED_END[name]))
    with open(copy, "w") as f:
        json.dump(data, f, indent=1)
    return copy


def check_scene(args, blender, scene):
    name = os.path.splitext(os.path.basename(scene))[0]
    out_dir = os.path.join(args.out, name)
    t0 = time.time()
    summary = bt.shellfrac_run(args.shellfrac, scene_to_run(scene, name, args.out), out_dir, threads=2)
    run_seconds = time.time() - t0
    bt.check(summary.get("status") == "completed", "%s: the run did not complete: %s" % (name, summary.get("error")))
    last = os.path.join(out_dir, summary["frames"][-1])
    t1 = time.time()
    record = bt.count_loose_parts(blender, last)
    blender_seconds = time.time() - t1
    count = record["welded"]  # patches joined along their seams, as `pieces` counts the whole body
    expected, why = expected_parts(summary)
    metrics = summary.get("metrics", {})
    cracks = metrics.get("cracks", {})
    print("%s: Blender counts %d loose part(s) in %s (%d objects, %d vertices); summary: pieces %s, slivers %s, "
          "max edge stretch %s, strand area %s, mls_failures %s; run %.1f s, Blender %.1f s"
          % (name, count, os.path.relpath(last, out_dir), len(record["objects"]), record["vertices"],
             metrics.get("pieces"), metrics.get("slivers"), metrics.get("max_edge_stretch"), metrics.get("strand_area"),
             cracks.get("mls_failures"), run_seconds, blender_seconds), flush=True)
    if args.count_only:
        return
    check_scene_criteria(name, summary)
    bt.check(expected is not None, "%s: %s; Blender counts %d loose parts in the last frame" % (name, why, count))
    bt.check(count == expected, "%s: Blender counts %d loose parts in %s, summary.json says pieces + slivers.count = "
             "%d + %d = %d" % (name, count, last, metrics["pieces"], metrics["slivers"]["count"], expected))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--list", metavar="SCENES_DIR")
    ap.add_argument("--shellfrac")
    ap.add_argument("--blender")
    ap.add_argument("--out")
    ap.add_argument("--count-only", action="store_true")
    ap.add_argument("scenes", nargs="*")
    args = ap.parse_args()
    if args.list:
        print("\n".join(fracture_scenes(args.list)))
        return
    bt.check(args.shellfrac and args.out and args.scenes, "give --shellfrac, --out and at least one scene")
    blender = bt.blender_program(args.blender)
    failures = []
    for scene in args.scenes:
        try:
            check_scene(args, blender, scene)
        except bt.Failure as e:
            failures.append(str(e))
    bt.check(not failures, "\n".join(failures))
    print("PASS" if not args.count_only else "counted %d scene(s)" % len(args.scenes))


if __name__ == "__main__":
    bt.main_guard(main)
