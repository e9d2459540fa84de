"""The slide (thesis 3.3.5, Eq. 3.6) says success only when the robot's own sensors say it
carried the object to its target; judged here by the simulator's ground truth, which the
robot never sees."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from atd.model import load_task
from atd.sim import load_description, make_robot
from atd.sim.scene import Scene, scene_from_task
from factories.registry import create
from tests.primitives.conftest import execute, last_reasons
from translator import translate

TRAY = Path(__file__).resolve().parents[1] / "data" / "slide_tray.xml"
TARGET = np.array([0.10, 0.08])  # where the task's tray pose, moved along the slide's 8 cm, puts it


def run_baxter(engine: str, scene: Scene) -> tuple:
    """The tray task on Baxter's right arm, in `scene` rather than where the task says."""
    task, _ = load_task(TRAY)
    estd = translate(task, create("baxter", "right")).estd
    robot = make_robot(load_description("baxter", "right"), scene, engine)
    outcome, executor = execute(estd, robot, task=task)
    return outcome, executor, robot


def tray(**changes) -> Scene:
    """The task's scene with its tray changed (`Body` fields)."""
    task, _ = load_task(TRAY)
    scene = scene_from_task(task, TRAY)
    return dataclasses.replace(scene, objects=(dataclasses.replace(scene.objects[0], **changes),))


@pytest.mark.parametrize("engine", ["mujoco", "pybullet"])
def test_a_slide_whose_object_is_missing_does_not_succeed(engine: str) -> None:
    """The task believes a tray is there; the table is empty. The range sensor, swept over
    where the tray's edges should be, sees no drop off a top, and the slide ends in an error."""
    outcome, executor, _ = run_baxter(engine, Scene())
    assert not outcome.succeeded, outcome.summary
    assert any(r.startswith("found no edge") for r in last_reasons(executor)), last_reasons(executor)


@pytest.mark.parametrize("arm", ["left", "right"])
def test_a_hand_without_a_range_sensor_to_find_the_tray_is_refused_the_slide(arm: str) -> None:
    """Tombatossals' hands (the SDH2, left; the Barrett, right) have no range sensor to find
    where the tray stands. With rubber fingertips they carry it, but a tray standing 1.9 cm off
    the task's pose ended 2.0 cm from its target and the slide said it had reached it
    (docs/slide.md; main translated it, and the slide moved nothing): the translation refuses
    the slide, saying why, and nothing runs that could say success."""
    task, _ = load_task(TRAY)
    result = translate(task, create("tombatossals", arm))
    assert result.estd is None
    refused = [d for d in result.diagnostics if d.code == "TRN001"]
    assert len(refused) == 1 and "finds where the object to slide stands" in refused[0].message, result.diagnostics
    assert "baxter" in (refused[0].hint or "")


@pytest.mark.parametrize("engine", ["mujoco", "pybullet"])
def test_a_slide_carries_a_tray_standing_off_its_believed_pose_to_its_target(engine: str) -> None:
    """The tray stands 1.9 cm from where the task says (1.5 cm across, 1.1 cm behind, turned
    7 degrees). The range sensor finds its edges; the hand presses where the task meant on
    it and drags it to its target (a slide that trusted the task's pose said success with the
    tray 2.3 cm off): success, and by ground truth the tray within 1 cm of its target."""
    turn = np.radians(-7.0)
    pose = np.eye(4)
    pose[:3, :3] = [[np.cos(turn), -np.sin(turn), 0], [np.sin(turn), np.cos(turn), 0], [0, 0, 1]]
    pose[:3, 3] = (0.085, -0.011, 0.015)
    outcome, executor, robot = run_baxter(engine, tray(pose=pose))
    off = float(np.linalg.norm(robot.object_pose()[:2, 3] - TARGET))
    assert outcome.succeeded, last_reasons(executor)
    assert off < 0.01, f"said slid, but the tray is {off * 100:.1f} cm from its target"


@pytest.mark.parametrize("engine", ["mujoco", "pybullet"])
def test_a_hand_that_slips_over_a_tray_too_heavy_to_drag_does_not_say_it_slid_it(engine: str) -> None:
    """The tray weighs 3 kg, not the 0.2 kg the task says: the table holds it harder than the
    pressing hand grips it, and the hand slips over its top (once: "slid to the target,
    pressing with 7.7 N" with the box where it started). The wrist feels the hand's own
    friction on the tray, not the tray's dragging on the table (MuJoCo), or the range sensor
    finds no trailing edge where the target puts it (PyBullet, whose hand slips over the tray
    with a drag nearer the carrying one): an error, never a success."""
    outcome, executor, robot = run_baxter(engine, tray(mass=3.0))
    moved = float(np.linalg.norm(robot.object_pose()[:2, 3] - (0.10, 0.0)))
    assert moved < 0.02, f"the tray moved {moved * 100:.1f} cm: this test no longer shows a slip"
    assert not outcome.succeeded, outcome.summary
    said = last_reasons(executor)
    assert any(r.startswith(("moved nothing", "the object is not at its target")) for r in said), said


def test_a_slide_that_leaves_the_tray_behind_short_of_its_target_does_not_say_it_slid_it() -> None:
    """A block fixed on the table stops the tray 1.5 cm short of its target; the hand slips
    over it the rest of the way and feels its own friction on the tray, not the tray's on the
    table (a slide that asked for the carrying drag over 80% of the way said success here)."""
    task, _ = load_task(TRAY)
    scene = scene_from_task(task, TRAY)
    block = dataclasses.replace(scene.objects[0], name="block", size=(0.12, 0.02, 0.01),
                                pose=np.array([[1, 0, 0, 0.10], [0, 1, 0, 0.135], [0, 0, 1, 0.005], [0, 0, 0, 1.0]]))
    outcome, executor, robot = run_baxter("mujoco", dataclasses.replace(scene, obstacles=(block,)))
    short = TARGET[1] - float(robot.object_pose()[1, 3])
    assert short > 0.01, f"the tray is {short * 100:.1f} cm short: this test no longer shows a tray left behind"
    assert not outcome.succeeded, outcome.summary
    assert any(r.startswith("left the object behind") for r in last_reasons(executor)), last_reasons(executor)
