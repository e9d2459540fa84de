"""Jaws close on a ball slowly: a jaw's edge meeting the ball's flank at the full closing
speed kicked it 3-10 cm on along the table, out of the search's reach (generalisation.toml,
base seed 27191; docs/robust-grasp.md, "The ball kicked by the closing jaws"). Objects that
slide keep the full speed: a touch moves them a fraction of a mm."""

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

MELFA = robot_info(load_description("melfa"))
OPEN = float(MELFA.hand.open[0])


def _jaws(q: float) -> Readings:
    """The Melfa's jaws at `q`, their pads touching nothing."""
    zeros = np.zeros(6)
    return Readings(time=0.0, arm_q=zeros, arm_dq=zeros, arm_effort=zeros, hand_q=np.array([q]),
                    hand_dq=np.zeros(1), hand_effort=np.zeros(1), tcp=np.eye(4), wrench=zeros, taxels={},
                    pad_force=np.zeros(2), range=None)


def _closing_speed(obj: str, q: float = OPEN) -> float:
    """m/s the guided jaws' closing reference moves at, the jaws at `q`, the task believing `obj`."""
    ctx = Context(info=MELFA, params={}, object=get(obj).object_info(0.1, 0.0), environment=None)
    ctx.blackboard.contact = True  # the correcting arm has found where to close
    hand = build_controller(Controller(name="close_until_force", params={}), "hand", ctx)
    hand.start(_jaws(q))
    period = MELFA.control_period
    before = hand.update(_jaws(q), period).hand.values[0]
    after = hand.update(_jaws(q), period).hand.values[0]
    return abs(float(after - before)) / period


@pytest.mark.parametrize(("obj", "speed"), (("ball", ROLLING_SPEED * 0.04), ("wood", 0.04)))
def test_jaws_close_on_a_ball_at_a_quarter_of_their_speed_and_on_a_block_at_full_speed(obj: str, speed: float) -> None:
    assert _closing_speed(obj) == pytest.approx(speed)
