"""A place puts the object, not the TCP, on its target: a grasp that found the object off
the hand's centre holds it there, and the wrist's weighing says where (docs/pick-and-place.md)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from atd.model import load_task
from atd.sim import load_description, make_robot
from atd.sim.scene import scene_from_task
from factories.registry import create
from tests.primitives.conftest import EXAMPLES, events, execute
from translator import translate

TASK = EXAMPLES / "pick_and_place.xml"
TARGET = np.array([0.10, 0.10])  # where the task puts the box down
OFF = 0.012  # m: the box truly stands this far along y from where the task believes it


def test_the_barrett_puts_a_box_it_holds_off_centre_down_on_the_target() -> None:
    """The Barrett's pinch closes along x and holds a box standing 12 mm off along y 12 mm off
    its centre; a place that put the TCP on the target set the box down 12 mm from it."""
    task, diagnostics = load_task(TASK)
    assert task is not None, diagnostics
    translation = translate(task, create("tombatossals", "right"))
    assert translation.ok, translation.diagnostics
    scene = scene_from_task(task, TASK)
    pose = scene.object.pose.copy()
    pose[1, 3] += OFF
    sim = make_robot(load_description("tombatossals", "right"), replace(scene, object=replace(scene.object, pose=pose)),
                     "mujoco")
    outcome, executor = execute(translation.estd, sim, task=task)
    assert outcome.succeeded, outcome.summary
    assert np.linalg.norm(sim.object_pose()[:2, 3] - TARGET) < 0.005, sim.object_pose()[:3, 3]
    placed = [c.get("reason") for r in events(executor) if r["transition"].startswith("put_down->")
              for c in r["conditions"] if c.get("reason")]
    assert any("weighed" in reason for reason in placed), placed
