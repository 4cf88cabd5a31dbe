"""The whole run a user waits for: a shipped scene run to a given end time by `shellfrac run`, frames and
all, optionally against a second binary, alternating A B A B in one sitting. Prints per run the wall and
CPU seconds, peak RSS, steps, the stage split and the outcome (pieces, peak edge stretch), then medians,
the ratio of the medians, and our cost per step beside the thesis's Table 4.3 row for the same tear.

    /usr/bin/python3 bench/whole_run.py                       # benchmark-tear to 0.7 s, build/bin/shellfrac
    /usr/bin/python3 bench/whole_run.py --vs /tmp/old/shellfrac --rounds 3
    /usr/bin/python3 bench/whole_run.py --scene scenes/tear-mode-one.json --end 0.5 --no-thesis

Needs a Release build. Timing is only meaningful on a quiet machine: run nothing else meanwhile.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

# Thesis Table 4.3, the row of Fig. 4.10 (the 100 x 100-cell tear benchmark-tear.json is sized after):
# 3,500 steps at 1.08 s each, about 63 minutes; the thesis ran it on 24 cores.
THESIS_FIG_4_10 = {"steps": 3500, "seconds_per_step": 1.08, "cores": 24, "quadrature_points": 160_000}


def run_once(binary, scene_path, threads):
    """One `shellfrac run`: wall by the clock, CPU and peak RSS from the child's resource usage."""
    with tempfile.TemporaryDirectory(prefix="whole-run-") as out:
        start = time.perf_counter()
        proc = subprocess.Popen([binary, "run", scene_path, "--out", out, "--threads", str(threads)],
                                stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        _, status, usage = os.wait4(proc.pid, 0)
        wall = time.perf_counter() - start
        err = proc.stderr.read()
        proc.stderr.close()
        code = os.waitstatus_to_exitcode(status)
        if code != 0:
            raise RuntimeError("%s exited with %d:\n%s" % (binary, code, err[-2000:]))
        with open(os.path.join(out, "summary.json")) as f:
            summary = json.load(f)
    metrics = summary.get("metrics", {})
    return {
        "wall": wall,
        "cpu": usage.ru_utime + usage.ru_stime,
        "rss_mb": usage.ru_maxrss / 1024.0,
        "steps": summary["steps"],
        "dt_min": summary.get("dt_min"),
        "stages": summary.get("stage_seconds", {}),
        "pieces": metrics.get("pieces"),
        "peak_stretch": (metrics.get("peak_edge_stretch") or {}).get("value"),
        "quadrature_points": summary.get("particle_counts", {}).get("quadrature_points"),
    }


def describe(label, r):
    stages = ", ".join("%s %.1f" % (k, v) for k, v in sorted(r["stages"].items(), key=lambda kv: -kv[1]) if v >= 0.05)
    return ("%s: wall %.1f s, CPU %.1f s, %.0f MB, %d steps (dt_min %.3g), pieces %s, peak edge stretch %s\n"
            "    stages (s): %s" % (label, r["wall"], r["cpu"], r["rss_mb"], r["steps"], r["dt_min"] or 0,
                                    r["pieces"], "%.3f" % r["peak_stretch"] if r["peak_stretch"] else "-", stages))


def scene_copy(scene, end, folder):
    with open(scene) as f:
        data = json.load(f)
    if end is not None:
        data.setdefault("time", {})["end"] = end
    path = os.path.join(folder, os.path.basename(scene))
    with open(path, "w") as f:
        json.dump(data, f, indent=1)
    return path


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--binary", default=os.path.join(ROOT, "build", "bin", "shellfrac"))
    p.add_argument("--vs", help="a second shellfrac binary, run alternately with the first")
    p.add_argument("--scene", default=os.path.join(ROOT, "scenes", "benchmark-tear.json"))
    p.add_argument("--end", type=float, default=0.7, help="simulated end time [s] (default 0.7; the scene's own with --end -1)")
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--rounds", type=int, default=1)
    p.add_argument("--no-thesis", action="store_true", help="leave out the Table 4.3 comparison")
    a = p.parse_args()
    if a.rounds < 1 or a.threads < 1:
        p.error("--rounds and --threads must be at least 1")
    for b in [a.binary] + ([a.vs] if a.vs else []):
        if not os.access(b, os.X_OK):
            p.error("no executable binary at %s (build first: bash scripts/build.sh Release)" % b)
    with tempfile.TemporaryDirectory(prefix="whole-run-scene-") as folder:
        scene = scene_copy(a.scene, None if a.end < 0 else a.end, folder)
        runs = {"A": [], "B": []}
        for r in range(a.rounds):
            for label, binary in (("A", a.binary), ("B", a.vs)):
                if binary is None:
                    continue
                res = run_once(binary, scene, a.threads)
                runs[label].append(res)
                print(describe("round %d %s (%s)" % (r + 1, label, binary), res), flush=True)

    def median(label, key):
        return statistics.median(x[key] for x in runs[label])

    print("\nmedians over %d round(s), %d threads:" % (a.rounds, a.threads))
    for label, binary in (("A", a.binary), ("B", a.vs)):
        if runs[label]:
            print("  %s %s: wall %.1f s, CPU %.1f s, %d steps, %.1f ms per step" % (
                label, binary, median(label, "wall"), median(label, "cpu"), median(label, "steps"),
                1e3 * median(label, "wall") / median(label, "steps")))
    if runs["B"]:
        print("  wall B / A = %.3f, CPU B / A = %.3f" % (median("B", "wall") / median("A", "wall"),
                                                        median("B", "cpu") / median("A", "cpu")))
    if not a.no_thesis:
        t = THESIS_FIG_4_10
        wall, cpu, steps = median("A", "wall"), median("A", "cpu"), median("A", "steps")
        qp = runs["A"][0]["quadrature_points"] or 0
        print("\n| | steps | wall per step | core-seconds per step | quadrature points | whole run |")
        print("|---|---|---|---|---|---|")
        print("| thesis Table 4.3, Fig. 4.10 (%d cores) | %d | %.2f s | %.1f | %dK | %.0f min |" % (
            t["cores"], t["steps"], t["seconds_per_step"], t["seconds_per_step"] * t["cores"],
            t["quadrature_points"] // 1000, t["steps"] * t["seconds_per_step"] / 60))
        print("| shellfrac (%d threads) | %d | %.1f ms | %.4f | %dK | %.1f s |" % (
            a.threads, steps, 1e3 * wall / steps, cpu / steps, qp // 1000, wall))
    return 0


if __name__ == "__main__":
    sys.exit(main())
