"""Jaws whose grip stays just under SATURATED_GRIP, the squeeze at its limit, press partly
through a finger's bare rim beside the pads (the Melfa's tape roll held at 10.0 and 10.7 N of
15 until the grasp's timeout, generalisation.toml, base seed 61379), and so do jaws counted
as gripping at 10.5-11 N only at the squeeze's limit with the weaker pad's contact at its edge
(such grips fell in the lift, docs/robust-grasp.md): they reopen, the arm moves along the
jaws' width towards where the weaker pad felt the object, and they close again there."""

from __future__ import annotations

import numpy as np

from atd.model.estd import Controller
from primitives.base import Context, Status
from primitives.hands.parallel_jaw import RIM_TIME
from primitives.registry import build_controller
from primitives.robot import Readings
from tests.primitives.melfa_jaws import GRASP_HEIGHT, MELFA, Position, closing_correction, still


def _images(column: int) -> dict[str, np.ndarray]:
    """Both pads feeling the object in the same `column` along the hand's x, counted from its
    -x side (the left pad's columns run along the hand's x, the right pad's against it)."""
    left, right = np.zeros((14, 6)), np.zeros((14, 6))
    left[:, column] = right[:, 5 - column] = 1.0
    return {"tactile_left": left, "tactile_right": right}


def _readings(position: Position = GRASP_HEIGHT, q: float = 0.03, pads: tuple[float, float] = (0.0, 0.0),
              column: int = 5) -> Readings:
    """The Melfa still, its jaws at `q`, pads pressing `pads` N in `column` (5: at their +x edge)."""
    return still(position, q=q, pads=pads, taxels=_images(column) if any(pads) else None)


def _press(pads: tuple[float, float], column: int) -> tuple[Context, object, float | None]:
    """A guided close pressed still with `pads` N felt in `column`: the blackboard, the hand,
    and when (s) the jaws began to reopen (None: they did not in 1.5 s)."""
    ctx = Context(info=MELFA, params={}, environment=None)
    ctx.blackboard.contact = True  # the correcting arm has found the object: close
    hand = build_controller(Controller(name="close_until_force", params={}), "hand", ctx)
    hand.start(_readings())
    period = MELFA.control_period
    for _ in range(50):  # 1 cm of closing on nothing yet
        hand.update(_readings(q=0.02), period)
    for tick in range(round(1.5 / period)):  # pressed still: the squeeze rises to its limit
        hand.update(_readings(q=0.015, pads=pads, column=column), period)
        if ctx.blackboard.jaws_empty or hand.status is not Status.RUNNING:
            return ctx, hand, tick * period if ctx.blackboard.jaws_empty else None
    return ctx, hand, None


def test_a_grip_held_under_saturated_grip_reopens_saying_the_side() -> None:
    """At 10.0 and 10.7 N of 15, under SATURATED_GRIP's 10.5 N, the squeeze at its limit."""
    ctx, hand, reopened_at = _press((10.0, 10.7), column=5)
    assert hand.status is Status.RUNNING and not ctx.blackboard.fingers_stopped
    assert reopened_at is not None and RIM_TIME < reopened_at < RIM_TIME + 0.5, reopened_at
    assert ctx.blackboard.jaws_rim is not None and ctx.blackboard.jaws_rim > 0.5  # the +x edge


def test_a_grip_counted_only_at_the_squeeze_limit_with_a_pad_edge_contact_reopens() -> None:
    """At 11.0 and 11.5 N the squeeze at its limit counts a grip; the weaker pad feeling it in
    its edge column, the rest is on the rim (such grips fell in the lift): reopen, the side -x."""
    ctx, hand, reopened_at = _press((11.0, 11.5), column=0)
    assert hand.status is Status.RUNNING and reopened_at is not None and reopened_at < RIM_TIME
    assert ctx.blackboard.jaws_rim is not None and ctx.blackboard.jaws_rim < -0.5


def test_the_same_grip_felt_inside_the_pads_is_a_grip() -> None:
    ctx, hand, reopened_at = _press((11.0, 11.5), column=3)
    assert reopened_at is None and hand.status is Status.DONE and ctx.blackboard.fingers_stopped


def test_the_arm_moves_along_the_jaws_to_that_side_and_closes_again_there() -> None:
    ctx, arm = closing_correction(_readings)
    period = MELFA.control_period
    ctx.blackboard.jaws_empty, ctx.blackboard.jaws_rim = True, 0.8  # reopening off a rim, the object at +x
    twists = [arm.update(_readings(), period).arm.twist[:3] for _ in range(40)]
    assert not ctx.blackboard.contact  # the jaws wait open
    assert all(t[0] > 0.0 and t[2] <= 0.0 for t in twists[1:]), twists  # along +x, not up to search elsewhere
    ctx.blackboard.jaws_empty, ctx.blackboard.jaws_rim = False, None  # the jaws are open again
    half = MELFA.hand.pads[0].half_size[0]
    arm.update(_readings((0.4 + half, 0.0, 0.02)), period)  # a pad's half width along: there
    assert ctx.blackboard.contact and arm.status is Status.RUNNING  # close again, here
