"""A jaw grip is done only once the correcting arm no longer rises off the support: the
Panda's jaws held a speaker's top edge for 1.5 s while its arm rose to take their press off
the table, then closed empty; the hand had already said it held the object, so neither side
looked again and the grasp waited out the task's 20 s (generalisation.toml, base seed 52391)."""

from __future__ import annotations

import numpy as np

from atd.model.estd import Controller
from atd.sim import load_description
from atd.sim.simrobot import robot_info
from primitives.base import Context, Status
from primitives.registry import build_controller
from primitives.robot import Readings

MELFA = robot_info(load_description("melfa"))


def _jaws(q: float, pads: float) -> Readings:
    """The Melfa's jaws still at `q`, each pad pressing `pads` N."""
    zeros = np.zeros(6)
    return Readings(time=0.0, arm_q=zeros, arm_dq=zeros, arm_effort=zeros, hand_q=np.array([q]),
                    hand_dq=np.zeros(1), hand_effort=np.zeros(1), tcp=np.eye(4), wrench=zeros, taxels={},
                    pad_force=np.full(2, pads), range=None)


def _gripping(arm_rising: bool) -> tuple[Context, object]:
    """A guided close whose pads press the grasp force, the arm rising off the support or not."""
    ctx = Context(info=MELFA, params={}, environment=None)
    ctx.blackboard.contact = True  # the correcting arm has found the object: close
    hand = build_controller(Controller(name="close_until_force", params={}), "hand", ctx)
    hand.start(_jaws(0.03, 0.0))
    ctx.blackboard.pressing = arm_rising
    for _ in range(50):  # 1 cm of closing on nothing yet
        hand.update(_jaws(0.02, 0.0), MELFA.control_period)
    for _ in range(2):  # both pads touch: press; the grasp force felt, the jaws still: gripped
        hand.update(_jaws(0.015, 15.0), MELFA.control_period)
    return ctx, hand


def test_a_grip_is_done_at_once_when_the_arm_does_not_rise() -> None:
    ctx, hand = _gripping(arm_rising=False)
    assert hand.status is Status.DONE and ctx.blackboard.fingers_stopped


def test_a_grip_lost_while_the_arm_rises_off_the_support_is_looked_for_again() -> None:
    ctx, hand = _gripping(arm_rising=True)
    assert hand.status is Status.RUNNING and not ctx.blackboard.fingers_stopped
    hand.update(_jaws(0.0, 0.0), MELFA.control_period)  # slipped out: the jaws closed on nothing
    assert hand.status is Status.RUNNING and ctx.blackboard.jaws_empty
