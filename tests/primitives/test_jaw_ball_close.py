"""Jaws without tactile pads close on a ball at ROLLING_SPEED, and let go of it as slowly:
a Baxter paddle's edge meeting the ball's flank at the full closing speed kicked it 5-6 cm
along the table, and paddles letting go of its flank at 7 cm/s sent it 5 cm off, out of the
search's reach (generalisation.toml, base seed 27191; docs/robust-grasp.md, "The ball kicked
by the jaws"). Tactile jaws feel the ball and the arm follows the touching pad; objects that
slide stop within a fraction of a mm: both keep the full speed."""

from __future__ import annotations

import numpy as np
import pytest

from atd.model.estd import Controller
from atd.sim import load_description
from atd.sim.library import get
from atd.sim.simrobot import robot_info
from primitives.base import Context
from primitives.hands.parallel_jaw import ROLLING_SPEED
from primitives.registry import build_controller
from primitives.robot import Readings

SPEED = 0.04  # m/s: close_until_force's closing_speed


def _jaws(info, q: float) -> Readings:
    """The jaws at `q`, their pads touching nothing."""
    zeros = np.zeros(len(info.arm_joints))
    return Readings(time=0.0, arm_q=zeros, arm_dq=zeros, arm_effort=zeros, hand_q=np.array([q]),
                    hand_dq=np.zeros(1), hand_effort=np.zeros(1), tcp=np.eye(4), wrench=np.zeros(6), taxels={},
                    pad_force=np.zeros(2), range=None)


def _close_on_nothing(robot: str, obj: str, source: str) -> list[tuple[float, float, bool]]:
    """A guided close, the jaws following their reference, until they have closed on nothing
    and opened again: per tick, the jaws' position, how fast the reference moved (m/s) and
    whether they were reopening."""
    info = robot_info(load_description(robot))
    ctx = Context(info=info, params={}, object=get(obj).object_info(0.1, 0.0), environment=None)
    ctx.blackboard.contact = True  # the correcting arm has found where to close
    hand = build_controller(Controller(name="close_until_force", params={"force_source": source}), "hand", ctx)
    q, period = float(info.hand.open[0]), info.control_period
    hand.start(_jaws(info, q))
    ticks = []
    for _ in range(round(10.0 / period)):
        reference = float(hand.update(_jaws(info, q), period).hand.values[0])
        ticks.append((q, abs(reference - q) / period, ctx.blackboard.jaws_empty))
        q = reference
        if ticks[-1][2] and not ctx.blackboard.jaws_empty:
            break
    return ticks[1:]


def test_paddles_close_on_a_ball_slowly_and_let_go_of_it_slowly_until_clear_of_its_width() -> None:
    ticks = _close_on_nothing("baxter", "ball", "motor")
    closing = [speed for _, speed, reopening in ticks if not reopening]
    assert closing and float(np.median(closing)) == pytest.approx(ROLLING_SPEED * SPEED)
    gap_of = robot_info(load_description("baxter")).hand.pad_surfaces
    width = get("ball").object_info(0.1, 0.0).widest

    def gap(q: float) -> float:
        left, right = gap_of(np.array([q]))[:2, :3, 3]
        return float(np.linalg.norm(left - right))

    within = [speed for q, speed, reopening in ticks if reopening and gap(q) < width]
    beyond = [speed for q, speed, reopening in ticks if reopening and gap(q) >= width]
    assert within and float(np.median(within)) == pytest.approx(ROLLING_SPEED * SPEED)
    assert beyond and max(beyond) > 2.0 * SPEED  # past the ball's width, back at the gripper's full speed


@pytest.mark.parametrize(("robot", "obj", "source"), (("baxter", "wood", "motor"), ("melfa", "ball", "tactile")))
def test_jaws_close_at_full_speed_on_what_does_not_roll_or_with_pads_that_feel_it(robot: str, obj: str,
                                                                                    source: str) -> None:
    closing = [speed for _, speed, reopening in _close_on_nothing(robot, obj, source) if not reopening]
    assert closing and float(np.median(closing)) == pytest.approx(SPEED)
