"""scripts/tear_report.py: the --strength-scale runs (one per factor, failure stresses scaled exactly,
a scene without a failure stress once) and its refusal of non-positive factors."""
import importlib.util
import json
import subprocess
import sys

from conftest import REPO, shellfrac_bin

SCRIPT = REPO / "scripts" / "tear_report.py"


def load_script():
    spec = importlib.util.spec_from_file_location("tear_report", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_scale_strength_multiplies_every_failure_stress_and_nothing_else(tiny_tear):
    tear_report = load_script()
    scene = tiny_tear
    scene["shells"].append(json.loads(json.dumps(scene["shells"][0])))
    scene["shells"][1]["material"]["fracture"]["failure_stress"] = 3e4
    assert tear_report.scale_strength(scene, 0.98) == 2
    assert scene["shells"][0]["material"]["fracture"]["failure_stress"] == 2e4 * 0.98
    assert scene["shells"][1]["material"]["fracture"]["failure_stress"] == 3e4 * 0.98
    assert scene["shells"][0]["material"]["fracture"]["fracture_energy"] == 80  # untouched
    assert scene["shells"][0]["material"]["E"] == 5e5


def test_strength_scale_runs_each_breakable_scene_once_per_factor(tmp_path, tiny_tear, tiny_drape):
    (tmp_path / "tiny-tear.json").write_text(json.dumps(tiny_tear))
    tiny_drape["time"]["end"] = 0.02
    (tmp_path / "tiny-drape.json").write_text(json.dumps(tiny_drape))
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, str(SCRIPT), "--shellfrac", str(shellfrac_bin()), "--out", str(out),
                           "--threads", "1", "--end", "tiny-tear=0.05", "--strength-scale", "0.9,1.1",
                           str(tmp_path / "tiny-tear.json"), str(tmp_path / "tiny-drape.json")],
                          capture_output=True, text=True, timeout=240)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    rows = [line.split()[0] for line in proc.stdout.splitlines()[1:]]
    assert rows == ["tiny-tear@0.9", "tiny-tear@1.1", "tiny-drape"]
    for factor in (0.9, 1.1):
        copy = json.loads((out / ("tiny-tear@%g.json" % factor)).read_text())
        assert copy["shells"][0]["material"]["fracture"]["failure_stress"] == 2e4 * factor
        assert copy["time"]["end"] == 0.05
        assert json.loads((out / ("tiny-tear@%g" % factor) / "summary.json").read_text())["status"] == "completed"


def test_strength_scale_refuses_a_factor_that_is_not_positive(tmp_path):
    proc = subprocess.run([sys.executable, str(SCRIPT), "--shellfrac", str(shellfrac_bin()), "--out", str(tmp_path),
                           "--strength-scale", "1,0"], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 2
    assert "--strength-scale" in proc.stderr
