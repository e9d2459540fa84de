"""Tombatossals, the UJI humanoid torso (thesis A.1), mapped as in thesis Table 7.3.

Two Mitsubishi PA10-7C arms with a JR3 wrist force-torque sensor each: the right one
carries the Barrett BH8-280 hand with Weiss tactile pads on the distal phalanges and the
palm (the default, `--arm right`), the left one the Schunk SDH2 with tactile pads on its
phalanges (`--arm left`). The SDH2 opposes its fingers by at most 90 degrees, so it
cannot make a hook grasp (A.1.2): a grasp asking for one is refused.
"""

from __future__ import annotations

from atd.model.controllers import SensorKind
from atd.model.vocabulary import HandShape, StateType
from factories.base import Arm, Hand, MappingRow, Sensor
from factories.kinds import MultiFingerFactory

_WRIST_FT = Sensor("wrist_ft", SensorKind.FORCE_TORQUE, "JR3 6-axis force-torque sensor between arm and hand")

# Neither hand's description has a posture with one finger stretched out: 'extend_finger'
# becomes 'extend' (every finger stretched), which points the same way.
_ONE_FINGER = {HandShape.EXTEND_FINGER: HandShape.EXTEND}
_BARRETT = Hand("Barrett BH8-280", "multi-finger", frozenset(HandShape) - set(_ONE_FINGER), _ONE_FINGER,
                max_opening=0.16)

_SDH2_NO_HOOK = ("the Schunk SDH2 cannot make a hook grasp: its finger opposition is limited to 90 degrees "
                 "(thesis A.1.2)")
_SDH2 = Hand(
    "Schunk SDH2", "multi-finger",
    frozenset(HandShape) - {HandShape.HOOK_GRASP, HandShape.HOOK_GRASP_PRESHAPE} - set(_ONE_FINGER),
    {HandShape.HOOK_GRASP: HandShape.CYLINDRICAL_GRASP,
     HandShape.HOOK_GRASP_PRESHAPE: HandShape.CYLINDRICAL_GRASP_PRESHAPE, **_ONE_FINGER},
    max_opening=0.14,
    cannot_grasp={HandShape.HOOK_GRASP: _SDH2_NO_HOOK, HandShape.HOOK_GRASP_PRESHAPE: _SDH2_NO_HOOK},
)

# Which pads hold an object (finger pads), and which count as any finger contact. The names
# are the pads' names in the hands' descriptions (the SDH2's thumb carries 'tactile_f3');
# a test checks every tactile sensor here is a pad of the simulated hand.
_FINGER_PADS = ("tactile_f1", "tactile_f2", "tactile_f3")
_BARRETT_SENSORS = (
    _WRIST_FT,
    *(Sensor(p, SensorKind.TACTILE, f"Weiss 5x8 pad on the distal phalanx of finger {p[-1]}") for p in _FINGER_PADS),
    Sensor("tactile_palm", SensorKind.TACTILE, "Weiss 6x14 pad on the palm"),
)
_SDH2_SENSORS = (
    _WRIST_FT,
    *(Sensor(p, SensorKind.TACTILE, f"Weiss pads on the phalanges of finger {p[-1]}") for p in _FINGER_PADS),
)

class TombatossalsFactory(MultiFingerFactory):
    name = "tombatossals"
    description = ("UJI humanoid torso: two PA10-7C 7-DOF arms with JR3 wrist force-torque sensors; Barrett "
                   "BH8-280 hand (right) or Schunk SDH2 (left), both with Weiss tactile pads (thesis A.1)")
    arms = (
        Arm("right", "right PA10-7C arm with the Barrett BH8-280 hand", _BARRETT, _BARRETT_SENSORS),
        Arm("left", "left PA10-7C arm with the Schunk SDH2 hand", _SDH2, _SDH2_SENSORS),
    )
    holding_pads = _FINGER_PADS
    refused_grasp_hint = "use the right arm (--arm right, Barrett hand) or another grasp shape"
    # Thesis Table 7.3 but the slide: nothing here finds where the object stands (docs/slide.md)
    primitives = MultiFingerFactory.primitives - {StateType.SLIDE}
    node_table = tuple(MappingRow("slide", "-", "-", "-") if row.abstract == "slide" else row
                       for row in MultiFingerFactory.node_table)
    lacks = {StateType.SLIDE: ("Tombatossals has no sensor that finds where the object to slide stands (no range "
                               "sensor along its approach axis): its slide would carry an object standing off the "
                               "task's pose as far off its target and say it reached it (docs/slide.md)",
                               "push the object instead (type=\"push\"), or translate for baxter")}
