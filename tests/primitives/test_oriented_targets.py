"""Oriented targets (issue 10): a path's `<pose>` keeps its rotation through translation,
as the hand's turn away from pointing down, and the arm ends turned so; a turn no arm
controller makes (past 90 degrees from top-down) is the factory's refusal, not a run."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from atd.cli import main
from atd.model import load_task
from atd.runtime.session import Run
from factories.registry import create
from translator import translate

# the hand turned 30 degrees about the world's y axis at (0.10, 0, 0.15)
TILTED = """<?xml version="1.0" encoding="UTF-8"?>
<statemachine>
  <state name="reach" type="move">
    <movement>free</movement>
    <hand_shape>open</hand_shape>
    <path><pose>{pose}</pose></path>
  </state>
  <state name="done" type="success"/>
  <state name="failed" type="failure"/>
  <transition origin="reach" destination="done"><success/></transition>
  <transition origin="reach" destination="failed"><timeout>20</timeout></transition>
</statemachine>
"""
PITCH_30 = "0.8660254 0 0.5 0.10  0 1 0 0.0  -0.5 0 0.8660254 0.15  0 0 0 1"
UPSIDE_DOWN = "1 0 0 0.10  0 -1 0 0.0  0 0 -1 0.15  0 0 0 1"


def _task(tmp_path: Path, pose: str) -> Path:
    path = tmp_path / "tilted.xml"
    path.write_text(TILTED.format(pose=pose))
    return path


@pytest.mark.parametrize("engine", ["mujoco", "pybullet"])
def test_the_melfa_ends_turned_as_the_pose_says(tmp_path: Path, engine: str) -> None:
    task, _ = load_task(_task(tmp_path, PITCH_30))
    factory = create("melfa")
    run = Run(translate(task, factory).estd, factory, engine=engine)
    assert run.execute().succeeded
    tcp = run.robot.read().tcp
    hand_z = tcp[:3, 2]
    assert np.degrees(np.arccos(-hand_z[2])) == pytest.approx(30.0, abs=2.5)  # 30 degrees off straight down
    assert np.linalg.norm(tcp[:3, 3] - (0.10, 0.0, 0.15)) < 0.005


def test_a_hand_turned_upside_down_is_refused_with_the_pose_named(tmp_path: Path) -> None:
    result = CliRunner().invoke(main, ["translate", str(_task(tmp_path, UPSIDE_DOWN)), "--robot", "melfa", "-q"])
    assert result.exit_code == 4, result.output
    assert "its <pose> turns the hand by roll 180" in result.output
