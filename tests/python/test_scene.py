"""Scenes from Python: the round trip of every shipped scene and the CLI's validation errors."""
import copy
import json

import pytest

import shellfrac
from conftest import SCENES

SHIPPED = sorted(SCENES.glob("*.json")) + sorted(SCENES.glob("brittle/*.json"))


def test_there_are_shipped_scenes():
    assert len(SHIPPED) >= 20


@pytest.mark.parametrize("path", SHIPPED, ids=lambda p: str(p.relative_to(SCENES).with_suffix("")))
def test_round_trip_of_every_shipped_scene(path):
    with open(path) as f:
        d = json.load(f)
    # The exact writer: what was read is written back, no default added, no key lost.
    assert shellfrac.Scene.from_dict(d, source=str(path)).to_dict() == d
    assert shellfrac.Scene.load(str(path)).to_dict() == d


def test_from_dict_does_not_keep_a_reference_to_the_dict(tiny_drape):
    scene = shellfrac.Scene.from_dict(tiny_drape)
    tiny_drape["shells"][0]["thickness"] = -1
    assert scene.to_dict()["shells"][0]["thickness"] == 0.001


def test_scene_properties(tiny_drape):
    scene = shellfrac.Scene.from_dict(tiny_drape)
    assert scene.name == "tiny-drape"
    assert scene.source == "<python>"
    assert scene.shell_names == ["cloth"]
    assert scene == shellfrac.Scene.from_json(json.dumps(tiny_drape))
    assert "OK" not in scene.validate()  # the description, as `shellfrac validate` prints after "OK"
    assert "cloth" in scene.validate()


def test_load_missing_file_names_the_file(tmp_path):
    missing = tmp_path / "nope.json"
    with pytest.raises(shellfrac.SceneError) as e:
        shellfrac.Scene.load(str(missing))
    assert e.value.file == str(missing)
    assert e.value.json_path == ""
    assert str(missing) in str(e.value)


def test_scene_error_is_a_value_error():
    assert issubclass(shellfrac.SceneError, ValueError)
    assert issubclass(shellfrac.SceneError, shellfrac.Error)


# The valid scene and bad cases of tests/scene/scene_validation_test.cpp (a mirror: same pointer, same
# words in the message). Each replaces one value of the valid scene (None: deletes the key).
VALID = {
    "name": "t",
    "time": {"end": 0.1, "frame_rate": 30, "cfl": 0.5},
    "output": {"format": "obj", "resolution": [4, 4]},
    "shells": [
        {"name": "a", "patch": {"type": "flat", "size": [1, 2], "cells": [4, 8]},
         "thickness": 0.001, "material": {"E": 1e5, "nu": 0.3, "density": 200}},
        {"name": "b", "patch": {"type": "control_net", "degree": [2, 1],
                                "knots_u": [0, 0, 0, 1, 1, 1], "knots_v": [0, 0, 1, 1],
                                "control_points": [[0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0], [1, 1, 1], [2, 1, 0]],
                                "weights": [1, 0.5, 1, 1, 0.5, 1]},
         "thickness": 0.002, "material": {"E": 1e6, "nu": 0.2, "density": 500}},
        {"name": "c", "patch": {"type": "cone", "radius_bottom": 1, "radius_top": 0.5, "height": 1,
                                "sweep_degrees": 90, "cells": [4, 2]},
         "thickness": 0.002, "material": {"E": 1e6, "nu": 0.2, "density": 500}},
    ],
}
DELETE = object()
BAD = [
    ("negative_thickness", "/shells/0/thickness", -0.001, "/shells/0/thickness", "must be > 0"),
    ("thickness_as_string", "/shells/0/thickness", "thin", "/shells/0/thickness", "expected a number, got string"),
    ("missing_thickness", "/shells/0/thickness", DELETE, "/shells/0/thickness", "required key is missing"),
    ("poisson_half", "/shells/0/material/nu", 0.5, "/shells/0/material/nu", "in (-1, 0.5)"),
    ("unknown_material_key", "/shells/0/material/Young", 1, "/shells/0/material/Young", "unknown key"),
    ("unknown_top_level_key", "/colour", "red", "/colour", "allowed here are"),
    ("unknown_patch_type", "/shells/0/patch/type", "sphere", "/shells/0/patch/type", 'allowed are "flat"'),
    ("flat_zero_cells", "/shells/0/patch/cells", [0, 4], "/shells/0/patch/cells/0", "in [1, 10000]"),
    ("flat_fractional_cells", "/shells/0/patch/cells", [2.5, 4], "/shells/0/patch/cells/0", "expected an integer"),
    ("knots_not_monotone", "/shells/1/patch/knots_u", [0, 0, 0.5, 0.2, 1, 1], "/shells/1/patch/knots_u",
     "non-decreasing"),
    ("net_size_mismatch", "/shells/1/patch/control_points", [[0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0]],
     "/shells/1/patch/control_points", "require 3 x 2 = 6"),
    ("net_negative_weight", "/shells/1/patch/weights/3", -1, "/shells/1/patch/weights/3", "must be > 0"),
    ("shells_missing", "/shells", DELETE, "/shells", "at least one shell or solid"),
    ("pin_outside_patch", "/pins", [{"shell": 0, "control_points": [[6, 0]]}], "/pins/0/control_points/0",
     "outside the patch"),
    ("pin_unknown_shell", "/pins", [{"shell": "nope", "region": {"u": [0, 0.1]}}], "/pins/0/shell",
     "no shell is named"),
    ("time_cfl_above_one", "/time/cfl", 1.5, "/time/cfl", "in (0, 1]"),
    ("output_unknown_format", "/output/format", "docx", "/output/format", "unknown mesh format"),
    ("fracture_unknown_damage_rule", "/shells/0/material/fracture",
     {"failure_stress": 1e4, "fracture_energy": 100, "damage_rule": "permanent"},
     "/shells/0/material/fracture/damage_rule", 'unknown value "permanent": allowed are "healing", "monotone"'),
    ("cut_outside_domain", "/shells/0/cuts", [{"points": [[0.5, 0.5], [1.5, 0.5]]}], "/shells/0/cuts/0/points",
     "vertex 1 (1.5, 0.5) lies outside the domain"),
    ("cut_self_intersecting", "/shells/0/cuts", [{"points": [[0.2, 0.2], [0.8, 0.8], [0.8, 0.2], [0.2, 0.8]]}],
     "/shells/0/cuts/0/points", "segment 0 intersects segment 2 (self-intersecting polyline)"),
    ("cracks_zero_extraction_interval", "/cracks", {"extraction_interval": 0}, "/cracks/extraction_interval",
     "value 0 is out of range: must be in [1, 1000000]"),
]


def replaced(doc, pointer, value):
    d = copy.deepcopy(doc)
    keys = [int(k) if k.isdigit() else k for k in pointer.strip("/").split("/")]
    parent = d
    for k in keys[:-1]:
        parent = parent[k]
    if value is DELETE:
        del parent[keys[-1]]
    else:
        parent[keys[-1]] = value
    return d


def test_the_valid_scene_is_valid():
    shellfrac.Scene.from_dict(VALID, source="good.json").validate()


@pytest.mark.parametrize("label,pointer,value,error_path,reason", BAD, ids=[b[0] for b in BAD])
def test_bad_scene_raises_scene_error_with_the_pointer(label, pointer, value, error_path, reason):
    d = replaced(VALID, pointer, value)
    with pytest.raises(shellfrac.SceneError) as e:
        # Reading catches most; the rest (pins, cuts against the patch) need the built geometry.
        shellfrac.Scene.from_dict(d, source="bad.json").validate()
    err = e.value
    assert err.file == "bad.json"
    assert err.json_path == error_path, str(err)
    assert reason in err.reason, str(err)
    assert "bad.json: " + error_path in str(err)
    with pytest.raises(shellfrac.SceneError) as e2:  # the same error through Simulation
        shellfrac.Simulation(shellfrac.Scene.from_dict(d, source="bad.json"))
    assert e2.value.json_path == error_path
