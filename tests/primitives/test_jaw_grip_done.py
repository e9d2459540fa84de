"""A jaw grip is done only once the correcting arm no longer rises off the support: the
Panda's jaws held a speaker's top edge for 1.5 s while its arm rose to take their press off
the table, then closed empty; the hand had already said it held the object, so neither side
looked again and the grasp waited out the task's 20 s (generalisation.toml, base seed 52391). And jaws
pressing on something their pads do not feel look again; jaws that sweep through nearly shut on an
object squeezed aside have not closed on nothing (issue 31, docs/empty-the-box.md)."""

from __future__ import annotations

import numpy as np

from atd.model.estd import Controller
from atd.sim import load_description
from atd.sim.simrobot import robot_info
from primitives.base import Context, Status
from primitives.hands.parallel_jaw import SHUT_STILL, UNFELT_TIME
from primitives.registry import build_controller
from primitives.robot import Readings

MELFA = robot_info(load_description("melfa"))


def _jaws(q: float, pads: float, dq: float = 0.0) -> Readings:
    """The Melfa's jaws at `q`, moving at `dq` (still by default), each pad pressing `pads` N."""
    zeros = np.zeros(6)
    return Readings(time=0.0, arm_q=zeros, arm_dq=zeros, arm_effort=zeros, hand_q=np.array([q]),
                    hand_dq=np.array([dq]), hand_effort=np.zeros(1), tcp=np.eye(4), wrench=zeros, taxels={},
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
    for _ in range(round(SHUT_STILL / MELFA.control_period) + 1):  # slipped out: the jaws shut, still
        hand.update(_jaws(0.0, 0.0), MELFA.control_period)
    assert hand.status is Status.RUNNING and ctx.blackboard.jaws_empty


def test_jaws_that_sweep_through_nearly_shut_and_back_onto_the_object_grip_it() -> None:
    """The Baxter's paddles, pressing off a lying spray can's axis, squeezed it aside: they swept
    from 8 to 0.8 mm a jaw in 40 ms and sprang back to 4.8 mm on the can, which they held 14 cm
    up while the grasp had said they closed on nothing (docs/empty-the-box.md). Here the
    Melfa's: pressing, through 0.5 mm at 0.3 m/s, back to 4 mm, still, the grasp force felt."""
    ctx = Context(info=MELFA, params={}, environment=None)
    ctx.blackboard.contact = True
    hand = build_controller(Controller(name="close_until_force", params={}), "hand", ctx)
    hand.start(_jaws(0.03, 0.0))
    period = MELFA.control_period
    for _ in range(50):  # 1 cm of closing on nothing yet
        hand.update(_jaws(0.02, 0.0), period)
    hand.update(_jaws(0.008, 15.0), period)  # both pads on the object: press
    for q, dq in ((0.005, -0.3), (0.0005, -0.3), (0.0005, 0.3), (0.004, 0.3)):  # squeezed aside, and back
        hand.update(_jaws(q, 15.0, dq), period)
        assert not ctx.blackboard.jaws_empty, q
    for _ in range(5):
        hand.update(_jaws(0.004, 15.0), period)
    assert hand.status is Status.DONE and ctx.blackboard.fingers_stopped and not ctx.blackboard.jaws_empty


def test_jaws_pressing_on_something_their_pads_do_not_feel_look_again() -> None:
    """The Melfa's fingers stood on a tape roll's rim beside their pads, pressing with the pads
    feeling nothing, until the task's timeout (PyBullet, the same campaign): after UNFELT_TIME
    of that the jaws count as closed on nothing, reopen, and the arm looks elsewhere."""
    ctx = Context(info=MELFA, params={}, environment=None)
    ctx.blackboard.contact = True
    hand = build_controller(Controller(name="close_until_force", params={}), "hand", ctx)
    hand.start(_jaws(0.03, 0.0))
    period = MELFA.control_period
    empty_at = []
    for tick in range(round(1.0 / period)):  # the jaws held at 3 cm, their pads touching nothing
        hand.update(_jaws(0.03, 0.0), period)
        if ctx.blackboard.jaws_empty:
            empty_at.append(tick * period)
    assert hand.status is Status.RUNNING
    assert empty_at and UNFELT_TIME <= empty_at[0] <= UNFELT_TIME + 0.15, empty_at


def test_a_grip_asked_more_than_the_gripper_gives_is_done_at_its_limit() -> None:
    """Baxter's gripper gives 20 N; a grasp asking 25 N (a heavy object's holding force)
    had its motor pressing all it gives, the jaws still, until the grasp's timeout."""
    baxter = robot_info(load_description("baxter"))
    ctx = Context(info=baxter, params={}, environment=None)
    ctx.blackboard.contact = True
    hand = build_controller(Controller(name="close_until_force", params={"grasp_force": 25.0, "force_source": "motor"}),
                            "hand", ctx)
    zeros = np.zeros(7)
    effort = float(baxter.hand.effort_limit[0])

    def jaws(q: float, pressing: float) -> Readings:
        return Readings(time=0.0, arm_q=zeros, arm_dq=zeros, arm_effort=zeros, hand_q=np.array([q]),
                        hand_dq=np.zeros(1), hand_effort=np.array([baxter.hand.closing[0] * pressing]), tcp=np.eye(4),
                        wrench=np.zeros(6), taxels={}, pad_force=np.zeros(2), range=None)

    hand.start(jaws(0.02, 0.0))
    for _ in range(3):  # the jaws still on the object, the motor pressing all it gives
        hand.update(jaws(0.01, effort), baxter.control_period)
    assert hand.status is Status.DONE, hand.status
    assert f"the gripper gives {effort:g} N" in hand.reason
