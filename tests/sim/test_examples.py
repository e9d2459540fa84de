"""Every example ATD builds a scene on both engines, its object at rest where the file puts
it, and every robot reaches that object top-down."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from atd.model import load_task
from atd.sim import load_description, variants
from atd.sim.scene import scene_from_task

EXAMPLES = sorted((Path(__file__).resolve().parents[2] / "examples").glob("*.xml"))
WITH_OBJECT = [p for p in EXAMPLES if load_task(p)[0].object is not None]


def _scene(path: Path):
    task, diagnostics = load_task(path)
    assert task is not None, diagnostics
    return scene_from_task(task, path)


def test_the_examples_with_an_object_are_found() -> None:
    assert len(WITH_OBJECT) >= 5


@pytest.mark.parametrize("path", WITH_OBJECT, ids=lambda p: p.stem)
def test_example_objects_rest_where_the_atd_puts_them(path: Path, melfa, robot_of, run, engine) -> None:
    scene = _scene(path)
    robot = robot_of(melfa, engine, scene)
    run(robot, 0.5)
    np.testing.assert_allclose(robot.object_pose()[:3, 3], scene.object.pose[:3, 3], atol=2e-3)


@pytest.mark.parametrize(("robot", "arm"), variants())
def test_every_robot_reaches_every_example_object_top_down(robot, arm) -> None:
    d = load_description(robot, arm)
    target = d.tcp_pose(np.array(d.home))
    for path in WITH_OBJECT:
        scene = _scene(path)
        for lift in (0.0, 0.1):
            target[:3, 3] = scene.object.pose[:3, 3] + (0, 0, lift)
            _, error = d.inverse_kinematics(target, np.array(d.home))
            assert error < 1e-4, f"{d.label} cannot reach the object of {path.name} top-down"
