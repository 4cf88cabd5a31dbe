"""How a sweep scales on Dask workers: the obstacle course run serially and on a LocalCluster of N worker
processes, alternately, in one sitting. Prints each run's wall time, the medians and the ratio

    dask wall / (serial wall / N)

which is 1 for perfect scaling (the aim is at most 1.15 with N = 2). It also prints the sum of the runs'
own wall times in each mode, which shows how much of the gap is the machine (two runs at once are slower
than one) and how much is scheduling.

    PYTHONPATH=build/python /usr/bin/python3 bench/sweep_scaling.py --rounds 3 --workers 2
"""
import argparse
import statistics
import sys
import tempfile
import time

from shellfrac import sweep, verify_course


def one(executor, course, config):
    with tempfile.TemporaryDirectory(prefix="sweep-scaling-") as out:
        start = time.perf_counter()
        rows = verify_course.run_course(out, course, config, executor=executor, draw=False)
        wall = time.perf_counter() - start
    done = [r for r in rows if r["status"] == "completed"]
    if len(done) != len(rows):
        print("  (%d of %d runs did not complete: %s)" % (len(rows) - len(done), len(rows), ", ".join(
            "%s-p%d-c%d" % (r["case"], r["degree"], r["cells"]) for r in rows if r["status"] != "completed")))
    return wall, sum(r["wall_seconds"] for r in done)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--course", default=verify_course.DEFAULT_COURSE)
    p.add_argument("--config", choices=("tiny", "full"), default="full")
    a = p.parse_args()
    serial, dask, serial_runs, dask_runs = [], [], [], []
    for r in range(a.rounds):
        wall, runs = one(None, a.course, a.config)
        serial.append(wall)
        serial_runs.append(runs)
        # The cluster's start-up is part of what a user waits for, so it is inside the timing.
        start = time.perf_counter()
        client = sweep.connect("local:%d" % a.workers)
        try:
            _, runs = one(client, a.course, a.config)
        finally:
            sweep.close(client)
        dask.append(time.perf_counter() - start)
        dask_runs.append(runs)
        print("round %d: serial %.2f s (runs %.2f s), dask %d workers %.2f s (runs %.2f s)" % (
            r + 1, serial[-1], serial_runs[-1], a.workers, dask[-1], dask_runs[-1]), flush=True)
    s, d = statistics.median(serial), statistics.median(dask)
    print("median: serial %.2f s, dask %.2f s; dask / (serial / %d) = %.3f; runs' own time %.2f s -> %.2f s (%.3fx)"
          % (s, d, a.workers, d / (s / a.workers), statistics.median(serial_runs),
             statistics.median(dask_runs), statistics.median(dask_runs) / statistics.median(serial_runs)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
