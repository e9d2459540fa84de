"""A fingertip pressed on the table beside the object is not a finger on it. The Barrett's
pinch preshape reaches 12 cm out and down to the table; closing beside an object off the
pinch line (generalisation.toml, base seed 44021, the (0.02, 0.14) place: the ball, the mug,
the duck), F1's pad met the object, then F2's pressed the table at 20 N for seconds while F1
closed past the object, and the grasp read "finger F1 missed the object" and shifted the hand
along the pinch line towards F2, away from the object. A pad on a box's foot stands as low
(9 mm), so where the pad touches against the object's believed footprint tells the two
apart, not its height."""

from __future__ import annotations

import numpy as np

from atd.model.estd import Controller
from atd.model.task import ObjectInfo, Pose
from atd.model.vocabulary import ObjectClass
from atd.sim import load_description
from atd.sim.simrobot import robot_info
from primitives.arm.motion import SUPPORT_BAND
from primitives.base import Context
from primitives.registry import build_controller
from primitives.robot import Readings

BARRETT = robot_info(load_description("tombatossals", "right"))
DOWN = np.diag([1.0, -1.0, -1.0])  # the hand pointing down
CLOSED_ON = np.array([np.pi / 2, 0.88, 0.81, 0.0])  # where the fingers stood still in the traced close
SPEAKER = (0.065, 0.05, 0.05)  # m: the library's speaker, a box


def _readings(q: np.ndarray, pressing: dict[str, float], height: float) -> Readings:
    """The Barrett still at `q`, each pad in `pressing` pressing that many N at its centre,
    F2's at `height` (m, world z)."""
    hand = BARRETT.hand
    tcp = np.eye(4)
    tcp[:3, :3], tcp[:3, 3] = DOWN, (0.4, 0.0, height + _f2_centre()[2])  # world z of F2's centre: height
    names = [p.name for p in hand.pads]
    pads = np.zeros(len(hand.pads))
    for pad, force in pressing.items():
        pads[names.index(pad)] = force
    zeros = np.zeros(BARRETT.arm_dof)
    return Readings(time=0.0, arm_q=zeros, arm_dq=zeros, arm_effort=zeros, hand_q=q.copy(),
                    hand_dq=np.zeros(len(q)), hand_effort=np.zeros(len(q)), tcp=tcp, wrench=np.zeros(6),
                    taxels={}, pad_force=pads, range=None)


def _f2_centre() -> np.ndarray:
    """F2's pad centre in the hand frame, the fingers where they stood still."""
    f2 = [p.name for p in BARRETT.hand.pads].index("tactile_f2")
    return BARRETT.hand.pad_surfaces(CLOSED_ON)[f2][:3, 3]


def _correction(height: float, speaker_from_pad: tuple[float, float]) -> np.ndarray:
    """The move the robust pinch asks for (hand frame, m) after a close on which F1's pad met
    the object, and whose fingers then stood still with F2's pad pressing 20 N at `height`
    and F1's feeling nothing, the task believing the speaker stands `speaker_from_pad` (m,
    world x, y) from F2's pad centre."""
    centre = DOWN @ _f2_centre() + (0.4, 0.0, 0.0)
    where = Pose.from_position((centre[0] + speaker_from_pad[0], centre[1] + speaker_from_pad[1], SPEAKER[2] / 2))
    speaker = ObjectInfo(pose=where, weight=0.15, object_class=ObjectClass.BOX, size=SPEAKER)
    ctx = Context(info=BARRETT, params={}, object=speaker)
    pinch = {"preshape": "pinch_grasp_preshape", "grasp_shape": "pinch_grasp"}
    hand = build_controller(Controller(name="robust_grasp_hand", params=pinch), "hand", ctx)
    pre = np.asarray(BARRETT.hand.postures["pinch_grasp_preshape"], float)
    period = BARRETT.control_period
    hand.start(_readings(pre, {}, 0.05))
    for _ in range(5):
        hand.update(_readings(pre, {}, 0.05), period)
    assert ctx.blackboard.preshaped
    ctx.blackboard.contact = True  # the arm has come down on the object, F1's pad on it: close
    for _ in range(5):
        hand.update(_readings(pre, {"tactile_f1": 10.0}, 0.02), period)
    for _ in range(round(1.0 / period)):  # the fingers stand still, F2's pad pressing
        hand.update(_readings(CLOSED_ON, {"tactile_f2": 20.0}, height), period)
    for _ in range(round(1.0 / period)):  # reopened into the preshape: the hand asks the arm to move
        hand.update(_readings(pre, {}, 0.05), period)
        if ctx.blackboard.shift is not None:
            return ctx.blackboard.shift.offset
    raise AssertionError("the hand asked for no correction")


def test_a_pad_pressed_on_the_table_beside_the_object_is_not_taken_for_it() -> None:
    """Pressed at 2 mm, 8 cm from where the speaker is believed to stand: the table. A search
    step across the pinch line (hand y), not a finger-lost shift along it (hand x) towards
    F2. Fails on main: +1.5 cm along x."""
    offset = _correction(0.2 * SUPPORT_BAND, (0.0, 0.08))
    assert abs(offset[0]) < 1e-6 and abs(offset[1]) > 0.01, offset


def test_a_pad_as_low_on_the_objects_foot_still_draws_the_hand_towards_that_finger() -> None:
    """The same press as low, but on the speaker's believed footprint (its face 2 mm beyond
    the pad): its foot. The finger-lost correction, towards F2 along x, as for a press 3 cm up."""
    for height in (0.2 * SUPPORT_BAND, 0.03):
        offset = _correction(height, (-SPEAKER[0] / 2 - 0.002, 0.0))
        assert offset[0] > 0.01 and abs(offset[1]) < 1e-6, (height, offset)
