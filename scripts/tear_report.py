#!/usr/bin/env python3
"""Runs the shipped tearing and cut scenes and prints one row of cleanliness metrics per scene.

    python3 scripts/tear_report.py [--shellfrac build/bin/shellfrac] [--out out/tears] [--threads 2]
                                   [--set grid.cracking_shells=pic ...] [--end plate-pressure=0.45 ...]
                                   [--strength-scale 0.98,1,1.02] [SCENE.json ...]

Without scenes it runs every shipped scene with a shell that can crack (a "fracture" material or
"cuts"). `--set KEY=VALUE` (JSON value, or a bare string) changes a dotted key in every scene's copy
(`*` for every element of a list: shells.*.material.fracture.residual_stiffness=0.001);
`--end NAME=T` runs one scene to another end time. `--strength-scale F1,F2,...` runs each scene once per
factor with every fracture material's failure_stress multiplied by it (rows NAME@F; a scene without a
failure stress runs once): a tear's outcome depends on its crack path, which is chaotic, so compare
settings over a few of these rather than on one run. Each row: pieces, slivers, the peak edge stretch over
all frames and its frame, the largest strand area of any frame, mls_failures, and the wall and CPU time
of the run. Standard library only.
"""
import argparse
import copy
import glob
import json
import os
import resource
import subprocess
import sys
import time


def can_crack(scene):
    return any("fracture" in s.get("material", {}) or s.get("cuts") for s in scene.get("shells", []))


def set_key(node, keys, value, create=True):
    """Sets node[keys[0]][keys[1]]... = value. A "*" key applies the rest to every element of a list, and
    below it only where the intermediate objects exist (shells.*.material.fracture.x skips unbreakable shells)."""
    head, rest = keys[0], keys[1:]
    if head == "*":
        for item in node:
            set_key(item, rest, value, create=False)
        return
    if not rest:
        node[head] = value
    elif head in node or create:
        set_key(node.setdefault(head, {}), rest, value, create)


def scale_strength(node, factor):
    """Multiplies every "failure_stress" number below node by factor; returns how many it changed."""
    changed = 0
    if isinstance(node, dict):
        for key, value in node.items():
            if key == "failure_stress" and isinstance(value, (int, float)):
                node[key] = value * factor
                changed += 1
            else:
                changed += scale_strength(value, factor)
    elif isinstance(node, list):
        changed = sum(scale_strength(item, factor) for item in node)
    return changed


def parse_value(text):
    try:
        return json.loads(text)
    except json.JSONDecodeError:
        return text


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ap.add_argument("--shellfrac", default=os.path.join(root, "build", "bin", "shellfrac"))
    ap.add_argument("--out", default=os.path.join(root, "out", "tears"))
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    ap.add_argument("--end", action="append", default=[], metavar="NAME=T")
    ap.add_argument("--strength-scale", default="", metavar="F1,F2,...")
    ap.add_argument("scenes", nargs="*")
    args = ap.parse_args()

    paths = args.scenes
    if not paths:
        paths = [p for p in sorted(glob.glob(os.path.join(root, "scenes", "*.json")))
                 if can_crack(json.load(open(p)))]
    ends = dict((k, float(v)) for k, v in (e.split("=", 1) for e in args.end))
    factors = [float(f) for f in args.strength_scale.split(",") if f.strip()]
    if any(not f > 0 for f in factors):
        ap.error("--strength-scale: every factor must be > 0")
    os.makedirs(args.out, exist_ok=True)
    print("%-24s %6s %7s %9s %5s %11s %4s %8s %8s %s" % ("scene", "pieces", "slivers", "peak_str", "frame",
                                                      "peak_strand", "mls", "wall_s", "cpu_s", "status"))
    failed = False
    runs = []
    for path in paths:
        base = os.path.splitext(os.path.basename(path))[0]
        with open(path) as f:
            scene = json.load(f)
        for item in args.set:
            key, value = item.split("=", 1)
            set_key(scene, key.split("."), parse_value(value))
        if base in ends:
            scene["time"]["end"] = ends[base]
        if not factors or not scale_strength(copy.deepcopy(scene), 1.0):  # nothing to scale: one run
            runs.append((base, scene))
            continue
        for factor in factors:
            variant = copy.deepcopy(scene)
            scale_strength(variant, factor)
            runs.append(("%s@%g" % (base, factor), variant))
    for name, scene in runs:
        out_dir = os.path.join(args.out, name)
        scene_copy = os.path.join(args.out, name + ".json")
        with open(scene_copy, "w") as f:
            json.dump(scene, f, indent=1)
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        t0 = time.time()
        proc = subprocess.run([args.shellfrac, "run", scene_copy, "--out", out_dir, "--threads", str(args.threads)],
                              stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        wall = time.time() - t0
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
        try:
            with open(os.path.join(out_dir, "summary.json")) as f:
                summary = json.load(f)
        except (OSError, json.JSONDecodeError):
            print("%-24s run failed (exit %d): %s" % (name, proc.returncode, proc.stderr.strip()[-300:]))
            failed = True
            continue
        m = summary.get("metrics", {})
        peak = m.get("peak_edge_stretch", {})
        print("%-24s %6s %7s %9.3f %5s %11.3g %4s %8.1f %8.1f %s" % (
            name, m.get("pieces"), m.get("slivers", {}).get("count"), peak.get("value", float("nan")),
            peak.get("frame"), m.get("peak_strand_area", float("nan")), m.get("cracks", {}).get("mls_failures"),
            wall, cpu, summary.get("status")), flush=True)
        failed = failed or summary.get("status") != "completed"
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
