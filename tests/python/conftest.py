"""Shared set-up of the Python tests: the package under build/python, the CLI, tiny scenes.

ctest runs these with PYTHONPATH=<build>/python and SHELLFRAC_BIN=<build>/bin/shellfrac (tests/python/CMakeLists.txt).
"""
import copy
import os
import pathlib

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
SCENES = REPO / "scenes"


def shellfrac_bin():
    return pathlib.Path(os.environ.get("SHELLFRAC_BIN", REPO / "build" / "bin" / "shellfrac"))


# A 0.4 m sheet of 6 x 6 cells dropped onto a sphere: a few hundred particles, a few dozen steps.
TINY_DRAPE = {
    "name": "tiny-drape",
    "time": {"end": 0.06, "frame_rate": 50},
    "output": {"format": "obj", "resolution": [8, 8], "precision": "double"},
    "shells": [{
        "name": "cloth",
        "patch": {"type": "flat", "size": [0.4, 0.4], "cells": [6, 6],
                  "origin": [-0.2, 0.2, 0.2], "axis_u": [1, 0, 0], "axis_v": [0, 0, -1]},
        "thickness": 0.001,
        "material": {"E": 2e4, "nu": 0.3, "density": 300},
    }],
    "colliders": [{"shape": "sphere", "center": [0, 0, 0], "radius": 0.15}],
}

# A notched strip pulled apart (mode I), small enough to tear in about a second of wall time.
TINY_TEAR = {
    "name": "tiny-tear",
    "time": {"end": 0.3, "frame_rate": 10},
    "output": {"format": "obj", "resolution": [16, 16]},
    "gravity": [0, 0, 0],
    "damping": 4.0,
    "shells": [{
        "name": "sheet",
        "patch": {"type": "flat", "size": [1.0, 1.0], "cells": [12, 12]},
        "thickness": 0.002,
        "material": {"E": 5e5, "nu": 0.3, "density": 500,
                     "fracture": {"failure_stress": 2e4, "fracture_energy": 80}},
        "cuts": [{"points": [[0.0, 0.5], [0.3, 0.5]]}],
    }],
    "pins": [
        {"shell": "sheet", "region": {"v": [0.0, 0.05]}},
        {"shell": "sheet", "region": {"v": [0.95, 1.0]},
         "motion": {"keyframes": [{"time": 0, "translation": [0, 0, 0]},
                                  {"time": 0.3, "translation": [0, 0.3, 0]}]}},
    ],
}


@pytest.fixture
def tiny_drape():
    return copy.deepcopy(TINY_DRAPE)


@pytest.fixture
def tiny_tear():
    return copy.deepcopy(TINY_TEAR)
