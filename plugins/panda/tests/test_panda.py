"""The panda robot passes atd's self-test and picks and places a box, in both engines.

Run with `python -m pytest tests` after `pip install -e .`; each case takes a few seconds.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ENGINES = ("mujoco", "pybullet")
PICK_AND_PLACE = Path(__file__).with_name("pick_and_place.xml")


def atd(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "atd", *args], capture_output=True, text=True, timeout=600)


@pytest.mark.parametrize("engine", ENGINES)
def test_it_passes_the_self_test(engine):
    result = atd("robots", "test", "panda", "--engine", engine)
    assert result.returncode == 0, result.stdout + result.stderr


@pytest.mark.parametrize("engine", ENGINES)
def test_it_picks_and_places_a_box(engine):
    result = atd("run", str(PICK_AND_PLACE), "--robot", "panda", "--engine", engine)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "outcome: succeeded" in result.stdout
