"""The three examples of examples/python, run at their --tiny sizes; their numbers checked."""
import json
import os
import subprocess
import sys

import numpy as np
import pytest

from conftest import REPO

EXAMPLES = REPO / "examples" / "python"


def run_example(name, out):
    env = dict(os.environ, MPLBACKEND="Agg")
    r = subprocess.run([sys.executable, str(EXAMPLES / name), "--tiny", "--threads", "2", "--out", str(out)],
                       env=env, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return r.stdout


def assert_png(path):
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 5000, path


def test_drape_energy(tmp_path):
    run_example("drape_energy.py", tmp_path)
    assert_png(tmp_path / "energy.png")
    t, e = np.loadtxt(tmp_path / "energy.csv", delimiter=",", skiprows=1).T
    # Free fall until the grid nodes the cloth touches (up to 2 cells of 0.125 m below it, starting 0.4 m
    # above the ball's top in the tiny variant) reach the sphere: every particle has v = g t, so
    # E = 1/2 M (g t)^2 with M = rho tau A = 300 * 0.0005 * 1 m^2 (the grid transfers keep a uniform
    # velocity exactly; symplectic Euler gives v = g t at every step end).
    free = t < 0.15  # measured: exact to 1e-12 until t = 0.19 s
    assert free.sum() > 5
    np.testing.assert_allclose(e[free], 0.5 * 0.15 * (9.81 * t[free]) ** 2, rtol=1e-9)
    assert e.max() > e[-1]  # the ball stops the fall


@pytest.fixture(scope="module")
def sweep(tmp_path_factory):
    """The sweep example run once for the tests below: its output folder and sweep.json's rows."""
    out = tmp_path_factory.mktemp("sweep")
    run_example("sweep_failure_stress.py", out)
    return out, json.loads((out / "sweep.json").read_text())


def test_sweep(sweep):
    out, rows = sweep
    assert_png(out / "sweep.png")
    assert [r["failure_stress"] for r in rows] == [1e4, 1.5e4, 2e4]
    assert all(r["status"] == "completed" for r in rows)
    # Every variant is cut by a crack that runs across the whole width, from the u = 0 edge (where the
    # notch starts) to the u = 1 edge: each crack graph reaches both edges (to 1e-9), so its length in the
    # parameter plane is at least 1, and the sheet is in at least two pieces.
    for r in rows:
        summary = json.loads((out / ("sigma_%g" % r["failure_stress"]) / "summary.json").read_text())
        (graph,) = summary["crack_graphs"]  # one sheet, one graph
        u = np.array(graph["vertices"], dtype=float).reshape(-1, 2)[:, 0]
        assert u.min() <= 1e-9 and u.max() >= 1 - 1e-9, (r["failure_stress"], u.min(), u.max())
        assert r["crack_length"] >= 1 - 1e-9, r
        assert r["pieces"] >= 2, r


@pytest.mark.xfail(strict=True, reason="known failure (2026-12-04): under the default cracking_shells "
                   "pic_while_damaged the 1.5e4 Pa variant also tears across below the pulled grip (v = 0.83), "
                   "giving pieces [2, 3, 2] (0.30, 0.53, 0.17 m^2); it passed under adaptive_then_pic")
def test_sweep_tears_every_variant_in_two(sweep):
    # The same pull tears every variant in two, one piece holding each pinned strip. (With G_f fixed, a
    # higher sigma_f is also a more brittle sheet, H = sigma_f^2 / (2 E G_f): since the crack graph closes
    # the strongest variant's damage band separates it too.)
    _, rows = sweep
    assert [r["pieces"] for r in rows] == [2, 2, 2]


def test_crack_graph(tmp_path):
    run_example("crack_graph.py", tmp_path)
    assert_png(tmp_path / "crack_graph.png")
    g = np.load(tmp_path / "crack_graph.npz")
    v, e = g["vertices"], g["edges"]
    assert len(e) > 0 and e.min() >= 0 and e.max() < len(v)
    assert ((v >= 0) & (v <= 1)).all()  # parameter plane of the flat patch
