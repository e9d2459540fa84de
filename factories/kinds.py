"""Mappings shared by every robot of a kind, so a new robot declares what it has and inherits
how its primitives and events are mapped.

`ParallelJawFactory`: one arm with a wrist force-torque sensor and a two-jaw gripper with a
tactile pad on each jaw, mapped as the Melfa is in thesis Table 7.4: grasp closes until the
pads feel the grasp force, transport keeps squeezing, place is a transport that stops on the
change of load the pads feel, release opens the jaws with the arm still, and there is no slide.
"""

from __future__ import annotations

from atd.model.controllers import SensorKind
from atd.model.task import State
from atd.model.vocabulary import EventType, StateType
from factories.base import ConditionNode, Factory, MappingContext, NodeMapping, Unmappable, all_of, any_of


class ParallelJawFactory(Factory):
    """A parallel-jaw robot as in thesis Table 7.4; its tactile sensors are the two jaws' pads."""

    primitives = frozenset({StateType.GRASP, StateType.MOVE, StateType.PUSH, StateType.TRANSPORT,
                            StateType.PLACE, StateType.RELEASE})

    def map_node(self, state: State, context: MappingContext) -> NodeMapping:
        kind = state.type
        if kind is StateType.SLIDE:
            raise Unmappable(f"the {self.name} has no slide primitive (a parallel jaw maps as thesis Table 7.4)",
                             "push the object instead (type=\"push\"), or translate for a robot that slides")
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

    def success(self, origin: State) -> ConditionNode:
        if origin.type is not StateType.PLACE:
            return super().success(origin)
        success = EventType.SUCCESS
        return all_of(any_of(self.condition(success, "arm_done"),
                             self.condition(success, "tactile_load_change", self.pads)),
                      self.condition(success, "hand_done"))

    def sensed_event(self, event_type: EventType, origin: State) -> ConditionNode:
        """Holding is both pads pressed; a contact is either one."""
        above = {EventType.GRASP_STABLE: 2, EventType.FINGER_CONTACT: 1}
        below = {EventType.GRASP_LOST: 2, EventType.FINGER_CONTACT_LOST: 1}
        if event_type in above:
            return self.condition(event_type, "tactile_force_above", self.pads, min_pads=above[event_type])
        if event_type in below:
            return self.condition(event_type, "tactile_force_below", self.pads, min_pads=below[event_type])
        return super().sensed_event(event_type, origin)

    @property
    def pads(self) -> tuple[str, ...]:
        return self.arm.sensors_of(SensorKind.TACTILE)
