"""Shared paths for the servo_axis_id tests (run by ctest: `ctest -L python`).

ctest sets PYTHONPATH to build/python (the module) and SERVO_AXIS_ID_BIN to
build/bin (simulate-axis, fit-params); run by hand from the repository root:
    PYTHONPATH=build/python python3 -m pytest python/tests
"""
import os
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
BIN = pathlib.Path(os.environ.get("SERVO_AXIS_ID_BIN", ROOT / "build" / "bin"))


@pytest.fixture
def root():
    return ROOT


@pytest.fixture
def bin_dir():
    return BIN
