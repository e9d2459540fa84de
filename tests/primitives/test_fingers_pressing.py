"""`fingers_pressing`, the hand's half of a look's `object_in_hand`: a closing joint that presses
short of the posture it was closing to, not one that presses where it made it
(docs/empty-the-box.md, "A look that starts with something in the hand")."""

from __future__ import annotations

import numpy as np

from atd.model.estd import Condition as Leaf
from atd.sim import load_description
from atd.sim.simrobot import robot_info
from primitives.base import Context, StateView, Status
from primitives.registry import build_condition
from primitives.robot import Readings, RobotInfo


def pressing(info: RobotInfo, q: np.ndarray, effort: np.ndarray) -> bool:
    """The verdict on the hand held at `q` with `effort` for 0.2 s (for_time 0.1 s)."""
    condition = build_condition(Leaf(kind="fingers_pressing", params={"posture": "closed", "for_time": 0.1}),
                                Context(info=info, params={}, environment=None))
    zeros = np.zeros(len(info.arm_joints))
    readings = Readings(time=0.0, arm_q=zeros, arm_dq=zeros, arm_effort=zeros, hand_q=q, hand_dq=np.zeros_like(q),
                        hand_effort=effort, tcp=np.eye(4), wrench=np.zeros(6), taxels={},
                        pad_force=np.zeros(len(info.hand.pads)), range=None)
    condition.start(readings)
    view = StateView(elapsed=0.0, arm=Status.ERROR, hand=Status.ERROR)
    return [condition.holds(readings, view, 0.01) for _ in range(20)][-1]


def test_the_baxter_s_paddles_held_2_mm_short_of_closed_on_a_duck_press_on_it():
    """The preset's seed 343, trial 0: the look's close stopped 2.0 mm a jaw from closed, 6 N."""
    info = robot_info(load_description("baxter"))
    closed = np.asarray(info.hand.postures["closed"], float)
    short = closed - info.hand.closing * 0.002
    assert pressing(info, short, info.hand.closing * 6.06)
    assert not pressing(info, short, np.zeros(1))  # short, but pressing on nothing: a hand still on its way


def test_the_sdh2_pressing_in_its_closed_posture_on_nothing_holds_nothing():
    """Its `closed` presses 0.174 N m (9 % of its proximal joints' limit) on nothing."""
    info = robot_info(load_description("tombatossals", "left"))
    closed = np.asarray(info.hand.postures["closed"], float)
    assert not pressing(info, closed, info.hand.closing * 0.174)
    assert pressing(info, closed - info.hand.closing * 0.2, info.hand.closing * 0.174)
