"""The slide (thesis 3.3.5, Eq. 3.6) says success only when the robot's own sensors say it
carried the object; judged here by the simulator's ground truth, which the robot never sees."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from atd.model import load_task
from atd.sim import load_description, make_robot
from atd.sim.scene import Scene
from factories.registry import create
from tests.primitives.conftest import execute, last_reasons, run_example
from translator import translate

TRAY = Path(__file__).resolve().parents[1] / "data" / "slide_tray.xml"


@pytest.mark.parametrize("engine", ["mujoco", "pybullet"])
def test_a_slide_whose_object_is_missing_does_not_succeed(engine: str) -> None:
    """The task believes a tray is there; the table is empty. The hand comes down on the
    table, below where the tray's top would be, and the slide ends in an error."""
    task, _ = load_task(TRAY)
    estd = translate(task, create("baxter", "right")).estd
    robot = make_robot(load_description("baxter", "right"), Scene(), engine)
    outcome, executor = execute(estd, robot, task=task)
    assert not outcome.succeeded, outcome.summary
    assert any(r.startswith("nothing to press on") for r in last_reasons(executor)), last_reasons(executor)


@pytest.mark.parametrize("engine", ["mujoco", "pybullet"])
def test_a_hand_that_slips_over_the_object_does_not_say_it_slid_it(engine: str) -> None:
    """Pressing on the tray's top with its friction no higher than the table's, the hand
    slips over it and the tray stays (once: "slid to the target, pressing with 7.7 N" with
    the box where it started). The wrist feels only the hand's own friction on the tray,
    not the tray's weight dragging on the table: an error, never a success."""
    outcome, executor, robot = run_example(TRAY, robot="baxter", arm="right", engine=engine)
    moved = float(np.linalg.norm(robot.object_pose()[:2, 3] - (0.10, 0.0)))
    assert moved < 0.02, f"the tray moved {moved * 100:.1f} cm: this test no longer shows a slip"
    assert not outcome.succeeded, outcome.summary
    assert any(r.startswith("moved nothing") for r in last_reasons(executor)), last_reasons(executor)
