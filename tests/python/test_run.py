"""shellfrac.run and Python stepping against the command-line tool."""
import json
import subprocess

import numpy as np
import pytest

import shellfrac
from conftest import shellfrac_bin

# Fields of summary.json that measure the machine, not the run.
CLOCK_FIELDS = ("wall_seconds", "stage_seconds")


def without_clocks(summary):
    s = json.loads(json.dumps(summary))
    for k in CLOCK_FIELDS:
        s.pop(k, None)
    for k in ("quadrature_point_steps_per_second", "quadrature_point_steps_per_second_per_core"):
        s["metrics"].pop(k, None)
    return s


def obj_vertices(path):
    rows = [line.split()[1:4] for line in open(path) if line.startswith("v ")]
    return np.array(rows, dtype=float)


def cli_run(scene_dict, out, threads):
    scene_file = out.parent / (out.name + ".json")
    scene_file.write_text(json.dumps(scene_dict))
    subprocess.run([str(shellfrac_bin()), "run", str(scene_file), "--out", str(out), "--threads", str(threads)],
                   check=True, capture_output=True)
    return json.loads((out / "summary.json").read_text())


@pytest.mark.parametrize("threads", [1, 2])
def test_python_stepping_is_bit_identical_to_the_cli(tiny_drape, tmp_path, threads):
    summary = cli_run(tiny_drape, tmp_path / "cli", threads)
    sim = shellfrac.Simulation(shellfrac.Scene.from_dict(tiny_drape), threads=threads)
    rate = tiny_drape["time"]["frame_rate"]
    assert len(summary["frames"]) == 4
    for f, frame in enumerate(summary["frames"]):
        sim.advance_to(f / rate)
        # 17 significant digits in the OBJ ("precision": "double") read back to the same doubles.
        assert np.array_equal(sim.render_mesh(0)["vertices"], obj_vertices(tmp_path / "cli" / frame)), frame
    assert sim.steps == summary["steps"]


def test_run_returns_the_summary_it_writes(tiny_drape, tmp_path):
    out = tmp_path / "py"
    summary = shellfrac.run(shellfrac.Scene.from_dict(tiny_drape), out=out, threads=1)
    assert summary == json.loads((out / "summary.json").read_text())
    assert summary["status"] == "completed" and summary["threads"] == 1
    # The same run as the CLI, frame files byte for byte.
    cli = cli_run(tiny_drape, tmp_path / "cli", 1)
    assert without_clocks(summary) | {"scene_source": None} == without_clocks(cli) | {"scene_source": None}
    for frame in summary["frames"]:
        assert (out / frame).read_bytes() == (tmp_path / "cli" / frame).read_bytes()


def test_run_accepts_a_dict_or_a_path(tiny_drape, tmp_path):
    s1 = shellfrac.run(tiny_drape, out=tmp_path / "a", threads=1)
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(tiny_drape))
    s2 = shellfrac.run(str(path), out=tmp_path / "b", threads=1)
    assert s1["steps"] == s2["steps"] and s1["metrics"]["final_kinetic_energy"] == s2["metrics"]["final_kinetic_energy"]


def test_run_failure_raises_numerical_error_after_writing_the_summary(tiny_drape, tmp_path):
    d = tiny_drape
    d["time"].update({"enforce_stability_bound": False, "dt": 0.01})
    d["shells"][0]["material"]["E"] = 1e9
    with pytest.raises(shellfrac.NumericalError) as e:
        shellfrac.run(d, out=tmp_path / "bad", threads=1)
    written = json.loads((tmp_path / "bad" / "summary.json").read_text())
    assert written["status"] == "failed" and written["error"] == str(e.value)
    assert e.value.shell == "cloth"


def test_run_bad_scene_raises_scene_error(tiny_drape, tmp_path):
    tiny_drape["shells"][0]["thickness"] = 0
    with pytest.raises(shellfrac.SceneError) as e:
        shellfrac.run(tiny_drape, out=tmp_path / "x")
    assert e.value.json_path == "/shells/0/thickness"
    assert not (tmp_path / "x").exists()  # nothing written before the scene is accepted


@pytest.mark.skipif(not shellfrac.run_interruptible,
                    reason="the run driver has no stop hook yet (output::RunOptions::should_stop)")
def test_keyboard_interrupt_stops_a_run_between_steps(tiny_drape, tmp_path):
    import _thread
    import threading

    tiny_drape["time"]["end"] = 1000.0  # hours unless interrupted
    timer = threading.Timer(0.5, _thread.interrupt_main)
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            shellfrac.run(tiny_drape, out=tmp_path / "int", threads=1)
    finally:
        timer.cancel()
    written = json.loads((tmp_path / "int" / "summary.json").read_text())
    assert written["status"] == "interrupted" and 0 < written["simulated_seconds"] < 1000.0
