"""Jaws whose grip stays just under SATURATED_GRIP, the squeeze at its limit, press partly
through a finger's bare rim beside the pads (the Melfa's tape roll held at 10.0 and 10.7 N of
15 until the grasp's timeout, generalisation.toml, base seed 61379): they reopen, the arm moves
along the jaws' width towards where the weaker pad felt the object, and they close again there."""

from __future__ import annotations

import numpy as np

from atd.model.estd import Controller
from atd.sim import load_description
from atd.sim.simrobot import robot_info
from primitives.base import Context, Status
from primitives.hands.parallel_jaw import RIM_TIME
from primitives.registry import build_controller
from primitives.robot import Readings

MELFA = robot_info(load_description("melfa"))
DOWN = np.diag([1.0, -1.0, -1.0])  # the hand pointing down, its x (the jaws' width) along the world's x


def _edge_images() -> dict[str, np.ndarray]:
    """Both pads feeling the object in their column at the hand's +x edge (the left pad's
    columns run along the hand's x, the right pad's against it)."""
    left, right = np.zeros((14, 6)), np.zeros((14, 6))
    left[:, 5] = right[:, 0] = 1.0
    return {"tactile_left": left, "tactile_right": right}


def _readings(position: tuple[float, float, float] = (0.4, 0.0, 0.02), q: float = 0.03,
              pads: tuple[float, float] = (0.0, 0.0)) -> Readings:
    """The Melfa still: its TCP at `position` pointing down, its jaws at `q`, pads pressing
    `pads` N at their +x edge."""
    tcp = np.eye(4)
    tcp[:3, :3], tcp[:3, 3] = DOWN, position
    zeros = np.zeros(6)
    return Readings(time=0.0, arm_q=zeros, arm_dq=zeros, arm_effort=zeros, hand_q=np.array([q]),
                    hand_dq=np.zeros(1), hand_effort=np.zeros(1), tcp=tcp, wrench=zeros,
                    taxels=_edge_images() if any(pads) else {}, pad_force=np.array(pads, float), range=None)


def test_a_grip_held_under_saturated_grip_reopens_saying_the_side() -> None:
    ctx = Context(info=MELFA, params={}, environment=None)
    ctx.blackboard.contact = True  # the correcting arm has found the object: close
    hand = build_controller(Controller(name="close_until_force", params={}), "hand", ctx)
    hand.start(_readings())
    period = MELFA.control_period
    for _ in range(50):  # 1 cm of closing on nothing yet
        hand.update(_readings(q=0.02), period)
    reopened_at = None
    for tick in range(round(1.5 / period)):  # pressed still at 10.0 and 10.7 N of 15: the squeeze saturates
        hand.update(_readings(q=0.015, pads=(10.0, 10.7)), period)
        if ctx.blackboard.jaws_empty:
            reopened_at = tick * period
            break
    assert hand.status is Status.RUNNING and not ctx.blackboard.fingers_stopped
    assert reopened_at is not None and RIM_TIME < reopened_at < RIM_TIME + 0.5, reopened_at
    assert ctx.blackboard.jaws_rim is not None and ctx.blackboard.jaws_rim > 0.5  # the +x edge


def test_the_arm_moves_along_the_jaws_to_that_side_and_closes_again_there() -> None:
    ctx = Context(info=MELFA, params={}, environment=None)
    arm = build_controller(Controller(name="jaw_grasp_correction", params={}), "arm", ctx)
    period = MELFA.control_period
    arm.start(_readings((0.4, 0.0, 0.08)))
    for _ in range(20):  # risen clear: the descent starts
        arm.update(_readings((0.4, 0.0, 0.10)), period)
    for _ in range(5):  # down at the grasp height without a contact: the jaws close
        arm.update(_readings(), period)
    assert ctx.blackboard.contact
    ctx.blackboard.jaws_empty, ctx.blackboard.jaws_rim = True, 0.8  # reopening off a rim, the object at +x
    twists = [arm.update(_readings(), period).arm.twist[:3] for _ in range(40)]
    assert not ctx.blackboard.contact  # the jaws wait open
    assert all(t[0] > 0.0 and t[2] <= 0.0 for t in twists[1:]), twists  # along +x, not up to search elsewhere
    ctx.blackboard.jaws_empty, ctx.blackboard.jaws_rim = False, None  # the jaws are open again
    half = MELFA.hand.pads[0].half_size[0]
    arm.update(_readings((0.4 + half, 0.0, 0.02)), period)  # a pad's half width along: there
    assert ctx.blackboard.contact and arm.status is Status.RUNNING  # close again, here
