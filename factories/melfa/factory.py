"""The Mitsubishi Melfa RV-3SB with the Weiss WRT-102 gripper (thesis A.3), as in Table 7.4.

A 6-DOF industrial arm with a JR3 wrist force-torque sensor and a PG70-based parallel
gripper with a tactile pad on each finger. Its primitives are simpler than Tombatossals'
(thesis 7.3): grasp closes until the tactile grasp force is reached, transport keeps
squeezing so the object does not loosen, place is a transport that descends straight onto
the surface, and there is no slide. A place ends in success only where the object meets the
surface the task puts it on: the pads' load changes as soon as the grip settles after a
grasp, so a place that ended on that (as it once did) could succeed without moving.
"""

from __future__ import annotations

from atd.model.controllers import SensorKind
from atd.model.task import State
from atd.model.vocabulary import EventType, StateType
from factories.base import (
    Arm,
    ConditionNode,
    Factory,
    Hand,
    MappingContext,
    MappingRow,
    NodeMapping,
    Sensor,
    Unmappable,
    PARALLEL_JAW_SHAPES,
    parallel_jaw_closest,
)

_PADS = ("tactile_left", "tactile_right")
_WRT102 = Hand("Weiss WRT-102 (Schunk PG70 based)", "parallel jaw",
               PARALLEL_JAW_SHAPES, parallel_jaw_closest(), max_opening=0.068)


class MelfaFactory(Factory):
    name = "melfa"
    description = ("Mitsubishi Melfa RV-3SB 6-DOF arm with a JR3 wrist force-torque sensor and the Weiss WRT-102 "
                   "parallel gripper (Schunk PG70 based) with a tactile pad on each finger (thesis A.3)")
    arms = (
        Arm("main", "Melfa RV-3SB arm with the WRT-102 gripper", _WRT102,
            (Sensor("wrist_ft", SensorKind.FORCE_TORQUE, "JR3 6-axis force-torque sensor between arm and gripper"),
             *(Sensor(p, SensorKind.TACTILE, f"Weiss tactile pad on the {p.split('_')[1]} finger") for p in _PADS))),
    )
    primitives = frozenset({StateType.GRASP, StateType.MOVE, StateType.PUSH, StateType.TRANSPORT,
                            StateType.PLACE, StateType.RELEASE})
    node_table = (  # thesis Table 7.4
        MappingRow("grasp", "grasp", "grasp force", "arm control, tactile sensors"),
        MappingRow("move", "move", "-", "arm control"),
        MappingRow("push", "move", "-", "arm control, force-torque sensor (feels the object)"),
        MappingRow("transport", "transport", "motion constraints", "arm control, tactile"),
        MappingRow("place", "transport", "motion constraints", "arm control, tactile"),
        MappingRow("slide", "-", "-", "-"),
        MappingRow("release", "release", "hand position", "arm control"),
    )

    def map_node(self, state: State, context: MappingContext) -> NodeMapping:
        kind = state.type
        if kind is StateType.SLIDE:
            raise Unmappable("the Melfa has no slide primitive (thesis Table 7.4)",
                             "push the object instead (type=\"push\"), or translate for tombatossals or baxter")
        if kind is StateType.GRASP:
            return self.jaw_grasp(state, context)
        if kind is StateType.RELEASE:  # Table 7.4: a hand position only, the arm stays
            return self.release(state, arm="hold")
        target, via = self.motion(state, context)
        # A place is a transport that ends on contact: it descends straight onto the surface.
        arm = self.arm_motion(state, target, via, **({"straight_line": True} if kind is StateType.PLACE else {}))
        if kind in (StateType.TRANSPORT, StateType.PLACE):
            return NodeMapping("transport", arm, self.controller("squeeze"))
        return NodeMapping("move", arm, *self.hand_for_motion(state))

    def sensed_event(self, event_type: EventType, origin: State) -> ConditionNode:
        if event_type is EventType.GRASP_STABLE:
            return self.condition(event_type, "tactile_force_above", _PADS, min_pads=2)
        if event_type is EventType.GRASP_LOST:
            return self.condition(event_type, "tactile_force_below", _PADS, min_pads=2)
        if event_type is EventType.FINGER_CONTACT:
            return self.condition(event_type, "tactile_force_above", _PADS, min_pads=1)
        if event_type is EventType.FINGER_CONTACT_LOST:
            return self.condition(event_type, "tactile_force_below", _PADS, min_pads=1)
        return super().sensed_event(event_type, origin)
