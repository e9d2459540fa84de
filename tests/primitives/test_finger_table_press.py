"""A fingertip pressed on the table is not a finger on the object. The Barrett's pinch
preshape reaches 12 cm out and down to the table; closing beside an object off the pinch line
(generalisation.toml, base seed 44021, the (0.02, 0.14) place: the ball, the mug, the duck),
F2's pad pressed the table at 20 N for seconds while F1 closed on nothing, and the grasp read
"finger F1 missed the object" and shifted the hand along the pinch line towards F2, spending
a correction and 3 s of the 20 s on a move the object had no part in. Judged by where the
pads touch, the close touched nothing above the table: the hand searches across the line."""

from __future__ import annotations

import numpy as np

from atd.model.estd import Controller
from atd.sim import load_description
from atd.sim.simrobot import robot_info
from primitives.arm.motion import SUPPORT_BAND
from primitives.base import Context
from primitives.registry import build_controller
from primitives.robot import Readings

BARRETT = robot_info(load_description("tombatossals", "right"))
DOWN = np.diag([1.0, -1.0, -1.0])  # the hand pointing down
CLOSED_ON = np.array([np.pi / 2, 0.88, 0.81, 0.0])  # where the fingers stood still in the traced close


def _readings(q: np.ndarray, f2: float, height: float) -> Readings:
    """The Barrett still at `q`, F2's pad pressing `f2` N at `height` (m, world z) at its centre."""
    hand = BARRETT.hand
    f2_pad = [p.name for p in hand.pads].index("tactile_f2")
    centre = hand.pad_surfaces(q)[f2_pad][:3, 3]  # hand frame
    tcp = np.eye(4)
    tcp[:3, :3], tcp[:3, 3] = DOWN, (0.4, 0.0, height + centre[2])  # world z of the centre: height
    pads = np.zeros(len(hand.pads))
    pads[f2_pad] = f2
    zeros = np.zeros(BARRETT.arm_dof)
    return Readings(time=0.0, arm_q=zeros, arm_dq=zeros, arm_effort=zeros, hand_q=q.copy(),
                    hand_dq=np.zeros(len(q)), hand_effort=np.zeros(len(q)), tcp=tcp, wrench=np.zeros(6),
                    taxels={}, pad_force=pads, range=None)


def _correction_after_pressing_at(height: float) -> np.ndarray:
    """The move the robust pinch asks for after a close whose fingers stood still with F2's pad
    pressing 20 N at `height` and F1's feeling nothing (hand frame, m)."""
    ctx = Context(info=BARRETT, params={})
    pinch = {"preshape": "pinch_grasp_preshape", "grasp_shape": "pinch_grasp"}
    hand = build_controller(Controller(name="robust_grasp_hand", params=pinch), "hand", ctx)
    pre = np.asarray(BARRETT.hand.postures["pinch_grasp_preshape"], float)
    period = BARRETT.control_period
    hand.start(_readings(pre, 0.0, 0.05))
    for _ in range(5):
        hand.update(_readings(pre, 0.0, 0.05), period)
    assert ctx.blackboard.preshaped
    ctx.blackboard.contact = True  # the arm has come down: close
    for _ in range(round(1.0 / period)):  # the fingers stand still, F2's pad pressing
        hand.update(_readings(CLOSED_ON, 20.0, height), period)
    for _ in range(round(1.0 / period)):  # reopened into the preshape: the hand asks the arm to move
        hand.update(_readings(pre, 0.0, 0.05), period)
        if ctx.blackboard.shift is not None:
            return ctx.blackboard.shift.offset
    raise AssertionError("the hand asked for no correction")


def test_a_pad_pressed_on_the_table_is_not_taken_for_the_object() -> None:
    """Pressed at 2 mm, on the table: a search step across the pinch line (hand y), not a
    finger-lost shift along it (hand x) towards F2. Fails on main: +1.5 cm along x."""
    offset = _correction_after_pressing_at(0.2 * SUPPORT_BAND)
    assert abs(offset[0]) < 1e-6 and abs(offset[1]) > 0.01, offset


def test_a_pad_pressed_on_the_object_still_draws_the_hand_towards_that_finger() -> None:
    """The same press 3 cm up, on the object: the finger-lost correction, towards F2 along x."""
    offset = _correction_after_pressing_at(0.03)
    assert offset[0] > 0.01 and abs(offset[1]) < 1e-6, offset
