"""A ball, or a cylinder on its side, set rolling on the table (a ball also on a box's floor)
slows down and stops, in both engines, as a real one does.

A grasp that nudges a ball must find it near where it was nudged: a ball that rolls on for
ever (MuJoCo without rolling friction) or speeds up (PyBullet's friction anchors, which pin
a contact point that a rolling ball does not have) leaves the search nothing to find.
"""

from __future__ import annotations

import numpy as np
import pybullet as pb
import pytest

from atd.sim import load_description
from atd.sim.library import get
from atd.sim.mujoco_engine import MujocoRobot
from atd.sim.scene import DEFAULT_FRICTION, Body, Container, Scene

RADIUS = 0.025  # m: the campaign library's rubber ball
SPEED = 0.05  # m/s along x, rolling without slipping


def _ball_scene(box: Container | None = None) -> Scene:
    """The ball on the table, or on the floor of `box`, 4 cm from its -x wall (24 cm from the other)."""
    pose = np.eye(4)
    pose[:3, 3] = (0.10, 0.0, RADIUS) if box is None else box.pose[:3, 3] + (-0.10, 0.0, box.wall + RADIUS)
    return Scene(Body("object", "sphere", (RADIUS,), pose, 0.07, DEFAULT_FRICTION),
                 containers=() if box is None else (box,))


def _roll(sim) -> None:
    """Start the ball rolling at SPEED along x, as a nudge would."""
    spin = SPEED / RADIUS  # about y, so the contact point stands still
    if isinstance(sim, MujocoRobot):
        sim.data.qvel[sim._object_dofs[0]] = (SPEED, 0.0, 0.0, 0.0, spin, 0.0)
    else:
        pb.resetBaseVelocity(sim.object, [SPEED, 0.0, 0.0], [0.0, spin, 0.0], physicsClientId=sim.client)


def _box() -> Container:
    """The box of docs/empty-the-box.md: 28 cm inside along x, its floor 1 cm thick."""
    pose = np.eye(4)
    pose[:3, 3] = (0.10, -0.08, 0.0)
    return Container("box", pose, (0.30, 0.25, 0.10), 0.01)


@pytest.mark.parametrize("where", ["table", "box"])
def test_a_rolling_ball_comes_to_rest_on_the_table_and_on_a_box_s_floor(engine, robot_of, where: str) -> None:
    """On a box's floor as on the table: anchored there (PyBullet), a ball a grasp had nudged in
    the box sped up from 2.5 to 14 cm/s and rolled from wall to wall for half a minute, so vision
    saw it where it no longer was (docs/empty-the-box.md, `pbv21`)."""
    sim = robot_of(load_description("melfa"), engine, _ball_scene(_box() if where == "box" else None))
    sim.hold_still(0.2)
    start = sim.object_pose()[:3, 3]
    _roll(sim)
    sim.hold_still(4.0)
    middle = sim.object_pose()[:3, 3]
    sim.hold_still(1.0)
    end = sim.object_pose()[:3, 3]
    rolled = float(np.linalg.norm(end[:2] - start[:2]))
    assert 0.001 < rolled < 0.08, rolled  # it rolled, a few centimetres (5 cm/s against 0.1 mm of rolling friction)
    assert float(np.linalg.norm(end[:2] - middle[:2])) < 0.001  # and it has stopped


def test_a_cylinder_rolling_on_its_side_slows_down_and_stops_on_the_table(engine, robot_of) -> None:
    """A can knocked over by a close rolls along the table and stops, as a real one does: anchored
    in PyBullet it sped up (15 to 24 cm/s in 2 s), in MuJoCo without rolling friction it kept its
    speed, and either rolled it off the table's edge (docs/robust-grasp.md, `pbw33`)."""
    can = get("cylinder")
    radius, speed = can.size[0], 0.10  # m/s along -y, rolling without slipping
    lying = np.eye(4)
    lying[:3, :3] = ((0.0, 0.0, 1.0), (0.0, 1.0, 0.0), (-1.0, 0.0, 0.0))  # its axis along x
    lying[:3, 3] = (0.3, 0.3, radius)
    sim = robot_of(load_description("melfa"), engine, Scene(can.body("object", lying)))
    sim.hold_still(0.2)
    start = sim.object_pose()[:3, 3]
    spin = np.array([speed / radius, 0.0, 0.0])  # about x, so the line on the table stands still
    if isinstance(sim, MujocoRobot):  # a free joint's turn is in the body's frame
        sim.data.qvel[sim._object_dofs[0]] = np.concatenate([(0.0, -speed, 0.0), sim.object_pose()[:3, :3].T @ spin])
    else:
        pb.resetBaseVelocity(sim.object, [0.0, -speed, 0.0], spin.tolist(), physicsClientId=sim.client)
    sim.hold_still(5.0)
    middle = sim.object_pose()[:3, 3]
    sim.hold_still(1.0)
    end = sim.object_pose()[:3, 3]
    rolled = float(np.linalg.norm(end[:2] - start[:2]))
    assert 0.05 < rolled < 0.3, rolled  # 10 cm/s against 0.1 mm of rolling friction: about 15 cm
    assert float(np.linalg.norm(end[:2] - middle[:2])) < 0.005  # and it has all but stopped (PyBullet creeps)
