"""Real-client check of a shipped fracture scene (issue 12): run it, import its last frame into Blender, and
assert that Blender's loose-part count equals metrics.pieces + metrics.slivers.count.

    python3 fracture_scene_test.py --list SCENES_DIR
        prints the fracture scenes (a shell with a "fracture" material or "cuts"), one path a line
    python3 fracture_scene_test.py --shellfrac BIN --out DIR [--blender B] [--count-only] SCENE.json...
        runs each scene at its shipped resolution with --threads 2; --count-only prints Blender's count and
        whatever summary.json has instead of asserting
"""
import argparse
import glob
import json
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


def check_scene(args, blender, scene):
    name = os.path.splitext(os.path.basename(scene))[0]
    out_dir = os.path.join(args.out, name)
    t0 = time.time()
    summary = bt.shellfrac_run(args.shellfrac, scene, out_dir, threads=2)
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
