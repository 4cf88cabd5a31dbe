"""Sweeps of scene variants (shellfrac.sweep) serially, on a Dask LocalCluster of 2 worker processes and on a
process pool, a worker killed mid-variant, and the obstacle course runner (shellfrac.verify_course)."""
import concurrent.futures
import copy
import csv
import json
import os
import signal
import subprocess
import sys
import threading
import time

import distributed
import numpy as np
import pytest

from shellfrac import sweep, verify_course
from conftest import REPO, TINY_DRAPE, shellfrac_bin


def drape(end, cells=6):
    d = copy.deepcopy(TINY_DRAPE)
    d["time"]["end"] = end
    d["time"]["frame_rate"] = 1.0 / end
    d["shells"][0]["patch"]["cells"] = [cells, cells]
    return d


# Three short drapes that differ in their cloth's stiffness, so that each has its own answer.
def short_variants():
    out = []
    for i, E in enumerate((1e4, 2e4, 4e4)):
        d = drape(0.1)
        d["shells"][0]["material"]["E"] = E
        out.append(sweep.Variant("drape-%d" % i, d, {"E": E}))
    return out


def last_frame(outcome):
    """The text of the run's last frame file."""
    return open(os.path.join(outcome.folder, outcome.summary["frames"][-1])).read()


@pytest.fixture(scope="module")
def client():
    c = sweep.connect("local:2")
    yield c
    sweep.close(c)


@pytest.fixture(scope="module")
def serial(tmp_path_factory):
    return sweep.run_sweep(short_variants(), tmp_path_factory.mktemp("serial"))


def test_serial_sweep_publishes_every_run(serial):
    assert [o.name for o in serial] == ["drape-0", "drape-1", "drape-2"]
    for o in serial:
        assert o.status == "completed" and o.attempts == 1 and o.error is None
        assert json.load(open(os.path.join(o.folder, "summary.json")))["steps"] == o.summary["steps"]
    root = os.path.dirname(serial[0].folder)
    assert sorted(os.listdir(root)) == ["drape-0", "drape-1", "drape-2", "sweep.json"]  # no .partial left
    recorded = json.load(open(os.path.join(root, "sweep.json")))["variants"]
    assert [(v["name"], v["status"], v["info"]["E"]) for v in recorded] == [("drape-0", "completed", 1e4),
                                                                           ("drape-1", "completed", 2e4),
                                                                           ("drape-2", "completed", 4e4)]


def test_dask_sweep_gives_the_serial_runs_bit_for_bit(client, serial, tmp_path):
    # One thread per run in both, so each variant's frames are deterministic: the Dask workers must give
    # byte-identical frames to the runs made in this process.
    outcomes = sweep.run_sweep(short_variants(), tmp_path, client)
    workers = {o.worker for o in outcomes}
    assert all(o.status == "completed" and o.attempts == 1 for o in outcomes)
    assert all(w.split(":")[1] != str(os.getpid()) for w in workers)  # ran in the worker processes
    for a, b in zip(outcomes, serial):
        assert last_frame(a) == last_frame(b)
        assert a.summary["steps"] == b.summary["steps"]


def test_any_executor_runs_a_sweep(serial, tmp_path):
    with concurrent.futures.ProcessPoolExecutor(2) as pool:
        outcomes = sweep.run_sweep(short_variants(), tmp_path, pool)
    for a, b in zip(outcomes, serial):
        assert a.status == "completed"
        assert last_frame(a) == last_frame(b)


def kill_while_running(root, name, times, found, sweep_over):
    """Kills the worker process running `name` (read from its run folder under .partial) `times` times,
    each time once a new attempt has started, until the sweep is over; appends the pids to `found`."""
    seen = set()
    while len(found) < times and not sweep_over.is_set():
        partial = os.path.join(root, ".partial")
        for entry in os.listdir(partial) if os.path.isdir(partial) else []:
            marker = os.path.join(partial, entry, "worker.txt")
            if entry.startswith(name + ".") and entry not in seen and os.path.exists(marker):
                text = open(marker).read().strip()
                if not text:
                    continue
                seen.add(entry)
                time.sleep(0.3)  # well inside the run (about 3 s)
                pid = int(text.split(":")[1])
                os.kill(pid, signal.SIGKILL)
                found.append(pid)
        time.sleep(0.02)


def sweep_with_kills(client, root, times):
    variants = [sweep.Variant("long", drape(16.0, cells=12))] + short_variants()
    killed, over = [], threading.Event()
    killer = threading.Thread(target=kill_while_running, args=(str(root), "long", times, killed, over))
    killer.start()
    try:
        outcomes = sweep.run_sweep(variants, root, client)
    finally:
        over.set()
        killer.join()
    return {o.name: o for o in outcomes}, killed


def test_a_worker_killed_mid_variant_costs_one_retry(client, serial, tmp_path):
    outcomes, killed = sweep_with_kills(client, tmp_path, 1)
    assert len(killed) == 1
    assert outcomes["long"].status == "completed" and outcomes["long"].attempts == 2
    assert outcomes["long"].worker.split(":")[1] != str(killed[0])
    for o, s in zip((outcomes["drape-%d" % i] for i in range(3)), serial):
        assert o.status == "completed"
        assert last_frame(o) == last_frame(s)
    assert not os.path.exists(tmp_path / ".partial")  # the dead attempt's folder is gone


def test_a_variant_whose_worker_dies_twice_is_lost_and_the_rest_kept(client, tmp_path):
    outcomes, killed = sweep_with_kills(client, tmp_path, 2)
    assert len(killed) == 2
    lost = outcomes["long"]
    assert lost.status == "lost" and lost.attempts == 2 and lost.summary is None
    assert "KilledWorker" in lost.error
    assert not os.path.exists(tmp_path / "long")  # nothing half-written under its name
    assert all(outcomes["drape-%d" % i].status == "completed" for i in range(3))
    recorded = {v["name"]: v["status"] for v in json.load(open(tmp_path / "sweep.json"))["variants"]}
    assert recorded == {"long": "lost", "drape-0": "completed", "drape-1": "completed", "drape-2": "completed"}


def test_a_new_run_replaces_the_old_folder_whole(tmp_path):
    (tmp_path / "drape-0").mkdir()
    (tmp_path / "drape-0" / "stale.txt").write_text("from an older sweep")
    [o] = sweep.run_sweep(short_variants()[:1], tmp_path)
    assert sorted(os.listdir(o.folder)) == ["frames", "summary.json"]


def test_bad_input_is_a_result_or_refused(tmp_path):
    bad = drape(0.1)
    bad["shells"][0]["material"]["nu"] = 0.7
    [o] = sweep.run_sweep([sweep.Variant("bad", bad)], tmp_path)
    assert o.status == "error" and "/shells/0/material/nu" in o.error and o.attempts == 1
    assert not os.path.exists(tmp_path / "bad")
    with pytest.raises(sweep.SweepError, match="given twice"):
        sweep.run_sweep([sweep.Variant("a", bad), sweep.Variant("a", bad)], tmp_path)
    with pytest.raises(sweep.SweepError, match="names a folder"):
        sweep.run_sweep([sweep.Variant("../escape", bad)], tmp_path)


def module_cli(module, *args, timeout=300):
    """Runs `python3 -m <module> ARGS` from the source tree with this interpreter's path."""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    return subprocess.run([sys.executable, "-m", module, *args], capture_output=True, text=True, cwd=REPO, env=env,
                          timeout=timeout)


def course_cli(*args, timeout=300):
    return module_cli("shellfrac.verify_course", *args, timeout=timeout)


def test_an_unreachable_scheduler_is_a_clear_error_within_ten_seconds(tmp_path):
    start = time.monotonic()
    r = course_cli("--config", "tiny", "--out", str(tmp_path), "--dask", "tcp://127.0.0.1:1", timeout=60)
    elapsed = time.monotonic() - start
    assert r.returncode == 2, r.stderr
    assert "cannot reach the Dask scheduler at tcp://127.0.0.1:1" in r.stderr
    assert elapsed < 10.0
    assert not os.path.exists(tmp_path / "verify.csv")


def test_course_table_is_the_runs_own_probes(client, tmp_path):
    rows = verify_course.run_course(tmp_path, REPO / "scenes" / "verification" / "course.json", "tiny",
                                    executor=client)
    course = json.load(open(REPO / "scenes" / "verification" / "course.json"))
    assert len(rows) == sum(len(c["tiny"]["cells"]) * len(c["tiny"]["degrees"]) for c in course["cases"])
    table = list(csv.DictReader(open(tmp_path / "verify.csv")))
    assert len(table) == len(rows)
    for row in table:
        case = next(c for c in course["cases"] if c["name"] == row["case"])
        s = json.load(open(tmp_path / "runs" / ("%s-p%s-c%s" % (row["case"], row["degree"], row["cells"])) /
                           "summary.json"))
        # The error recomputed from the run's own summary and the course's reference: the probe's last
        # value, or for a period the mean spacing of the crossings that numpy finds.
        z = np.array([d["xyz".index(case["component"])] for d in s["probes"][0]["displacement"]])
        if case.get("measure") == "period":
            t = np.array(s["probes"][0]["time"])
            i = np.nonzero(np.sign(z[1:]) * np.sign(z[:-1]) < 0)[0]
            crossings = t[i] - z[i] * (t[i + 1] - t[i]) / (z[i + 1] - z[i])
            value = 2 * (crossings[-1] - crossings[0]) / (len(crossings) - 1)
        else:
            value = case["sign"] * z[-1]
        assert float(row["error_pct"]) == pytest.approx(100 * (value / case["reference"] - 1), rel=1e-5)
        assert int(row["dofs"]) == 3 * s["particle_counts"]["control_points"]
        assert s["shellfrac_version"] and row["status"] == "completed"
    assert os.path.getsize(tmp_path / "verify-error-vs-time.png") > 10000


def test_presets_and_goals_follow_the_rows():
    def row(case, degree, cells, err, wall):
        return {"case": case, "degree": degree, "cells": cells, "error_pct": err, "wall_seconds": wall,
                "status": "completed"}
    rows = [row("a", 2, 8, -5.0, 1.0), row("a", 3, 8, -0.9, 3.0), row("a", 4, 8, 0.5, 2.0), row("a", 4, 16, 0.2, 9.0),
            row("b", 3, 16, 1.5, 1.0)]
    p = verify_course.presets(rows)
    assert (p["a"]["degree"], p["a"]["cells"]) == (4, 8) and p["b"] is None
    g = {(case, cells): met for case, cells, _, _, met in verify_course.goals(rows)}
    assert g == {("a", 16): True, ("a", 8): True, ("b", 16): False, ("b", 8): None}


def test_a_bad_course_names_the_file_and_path(tmp_path):
    (tmp_path / "course.json").write_text(json.dumps({"cases": [{"name": "x", "scene": "x.json", "probe": "p",
                                                                 "component": "w", "reference": 1, "cells": [4],
                                                                 "degrees": [2]}]}))
    r = course_cli("--course", str(tmp_path / "course.json"), "--out", str(tmp_path / "o"), timeout=60)
    assert r.returncode == 2
    assert "course.json: /cases/0/component: one of x, y, z" in r.stderr


def free_port():
    import socket
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_cli_runs_the_course_on_a_separate_scheduler_and_workers(tmp_path):
    # The documented multi-machine set-up on one machine: dask-scheduler and dask-worker processes, and
    # `shellfrac bench verify --dask tcp://...` from the command-line tool.
    port = free_port()
    env = dict(os.environ, DASK_DISTRIBUTED__SCHEDULER__ALLOWED_FAILURES="0")
    scheduler = subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_scheduler", "--port", str(port),
                                  "--dashboard-address", ":0"], env=env, stdout=subprocess.DEVNULL,
                                 stderr=subprocess.DEVNULL)
    workers = subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_worker", "tcp://127.0.0.1:%d" % port,
                                "--nworkers", "2", "--nthreads", "1"], env=env, stdout=subprocess.DEVNULL,
                               stderr=subprocess.DEVNULL)
    try:
        client = distributed.Client("tcp://127.0.0.1:%d" % port, timeout=30)
        client.wait_for_workers(2, timeout=30)
        client.close()
        r = subprocess.run([str(shellfrac_bin()), "bench", "verify", "--config", "tiny", "--no-charts", "--out",
                            str(tmp_path), "--dask", "tcp://127.0.0.1:%d" % port], capture_output=True, text=True,
                           cwd=REPO, timeout=300)
    finally:
        workers.terminate()
        scheduler.terminate()
        workers.wait(30)
        scheduler.wait(30)
    assert r.returncode == 0, r.stderr
    course = json.load(open(REPO / "scenes" / "verification" / "course.json"))
    expected = sum(len(c["tiny"]["cells"]) * len(c["tiny"]["degrees"]) for c in course["cases"])
    recorded = json.load(open(tmp_path / "runs" / "sweep.json"))["variants"]
    assert {v["status"] for v in recorded} == {"completed"} and len(recorded) == expected
    assert all(v["worker"].split(":")[1] != str(os.getpid()) for v in recorded)
    assert len(list(csv.DictReader(open(tmp_path / "verify.csv")))) == expected


def sweep_cli(*args):
    return module_cli("shellfrac.sweep_cli", *args)


def test_sweep_cli_runs_every_combination_of_the_values(serial, tmp_path):
    scene = tmp_path / "drape.json"
    scene.write_text(json.dumps(drape(0.1)))
    r = sweep_cli(str(scene), "--vary", "shells.0.material.E=1e4,2e4,4e4", "--vary", 'grid.transfer="adaptive"',
                  "--out", str(tmp_path / "out"), "--dask", "local:2")
    assert r.returncode == 0, r.stderr
    rows = list(csv.DictReader(open(tmp_path / "out" / "sweep.csv")))
    assert [(row["variant"], float(row["shells.0.material.E"]), row["grid.transfer"], row["status"]) for row in rows] == [
        ("v000", 1e4, '"adaptive"', "completed"), ("v001", 2e4, '"adaptive"', "completed"),
        ("v002", 4e4, '"adaptive"', "completed")]
    # The same runs as short_variants() made in this process: the same frames.
    for i, s in enumerate(serial):
        frame = open(tmp_path / "out" / ("v%03d" % i) / s.summary["frames"][-1]).read()
        assert frame == last_frame(s)


@pytest.mark.parametrize("vary, message", [
    ("shells.3.material.E=1", "shells has no element 3"),
    ("shells.0.material.E=abc", "value 'abc' is not JSON"),
    ("shells.0.material.nu=0.7", "/shells/0/material/nu"),
    ("shells.0.material.E", "write PATH=VALUE"),
])
def test_sweep_cli_refuses_bad_input_before_running(tmp_path, vary, message):
    scene = tmp_path / "drape.json"
    scene.write_text(json.dumps(drape(0.1)))
    r = sweep_cli(str(scene), "--vary", vary, "--out", str(tmp_path / "out"))
    assert r.returncode == 2, r.stderr
    assert message in r.stderr
    assert not os.path.exists(tmp_path / "out")
