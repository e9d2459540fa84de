"""The Mitsubishi Melfa RV-3SB with the Weiss WRT-102 gripper (thesis A.3), as in Table 7.4.

A 6-DOF industrial arm with a JR3 wrist force-torque sensor and a PG70-based parallel
gripper with a tactile pad on each finger. Its primitives are simpler than Tombatossals'
(thesis 7.3): grasp closes until the tactile grasp force is reached, transport keeps
squeezing so the object does not loosen, and there is no slide. Place is the place primitive,
not the thesis's transport descending onto the surface: it weighs where the jaws hold the
object on the JR3 and puts the object, not the TCP, on the target (`ParallelJawFactory`).
"""

from __future__ import annotations

from atd.model.controllers import SensorKind
from atd.model.vocabulary import StateType
from factories.base import Arm, Hand, Sensor, PARALLEL_JAW_SHAPES, parallel_jaw_closest
from factories.kinds import ParallelJawFactory

_PADS = ("tactile_left", "tactile_right")
_WRT102 = Hand("Weiss WRT-102 (Schunk PG70 based)", "parallel jaw",
               PARALLEL_JAW_SHAPES, parallel_jaw_closest(), max_opening=0.068)


class MelfaFactory(ParallelJawFactory):
    name = "melfa"
    description = ("Mitsubishi Melfa RV-3SB 6-DOF arm with a JR3 wrist force-torque sensor and the Weiss WRT-102 "
                   "parallel gripper (Schunk PG70 based) with a tactile pad on each finger (thesis A.3)")
    arms = (
        Arm("main", "Melfa RV-3SB arm with the WRT-102 gripper", _WRT102,
            (Sensor("wrist_ft", SensorKind.FORCE_TORQUE, "JR3 6-axis force-torque sensor between arm and gripper"),
             *(Sensor(p, SensorKind.TACTILE, f"Weiss tactile pad on the {p.split('_')[1]} finger") for p in _PADS))),
    )
    lacks = {StateType.SLIDE: ("the Melfa has no slide primitive (thesis Table 7.4)",
                               "push the object instead (type=\"push\"), or translate for baxter")}
