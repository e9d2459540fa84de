"""Tombatossals, the UJI humanoid torso (thesis A.1), mapped as in thesis Table 7.3.

Two Mitsubishi PA10-7C arms with a JR3 wrist force-torque sensor each: the right one
carries the Barrett BH8-280 hand with Weiss tactile pads on the distal phalanges and the
palm (the default, `--arm right`), the left one the Schunk SDH2 with tactile pads on its
phalanges (`--arm left`). The SDH2 opposes its fingers by at most 90 degrees, so it
cannot make a hook grasp (A.1.2): a grasp asking for one is refused.
"""

from __future__ import annotations

from atd.model.controllers import SensorKind
from atd.model.task import State
from atd.model.vocabulary import EventType, HandShape, StateType
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
    grasp_width,
    obstacle_params,
)

_WRIST_FT = Sensor("wrist_ft", SensorKind.FORCE_TORQUE, "JR3 6-axis force-torque sensor between arm and hand")

_BARRETT = Hand("Barrett BH8-280", "multi-finger", frozenset(HandShape), {}, max_opening=0.16)

_SDH2_NO_HOOK = ("the Schunk SDH2 cannot make a hook grasp: its finger opposition is limited to 90 degrees "
                 "(thesis A.1.2)")
_SDH2 = Hand(
    "Schunk SDH2", "multi-finger",
    frozenset(HandShape) - {HandShape.HOOK_GRASP, HandShape.HOOK_GRASP_PRESHAPE},
    {HandShape.HOOK_GRASP: HandShape.CYLINDRICAL_GRASP,
     HandShape.HOOK_GRASP_PRESHAPE: HandShape.CYLINDRICAL_GRASP_PRESHAPE},
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

# The grasp a hand closes into when the task names none, and the preshape that precedes each grasp.
DEFAULT_GRASP = HandShape.POWER_GRASP
_PRESHAPE_OF = {
    HandShape.POWER_GRASP: HandShape.POWER_GRASP_PRESHAPE,
    HandShape.PINCH_GRASP: HandShape.PINCH_GRASP_PRESHAPE,
    HandShape.CYLINDRICAL_GRASP: HandShape.CYLINDRICAL_GRASP_PRESHAPE,
    HandShape.SPHERICAL_GRASP: HandShape.SPHERICAL_GRASP_PRESHAPE,
    HandShape.HOOK_GRASP: HandShape.HOOK_GRASP_PRESHAPE,
}
_GRASP_OF = {pre: grasp for grasp, pre in _PRESHAPE_OF.items()}
PREGRASP_MARGIN = 0.04  # m of clearance around the object when the hand preshapes (ours)


class TombatossalsFactory(Factory):
    name = "tombatossals"
    description = ("UJI humanoid torso: two PA10-7C 7-DOF arms with JR3 wrist force-torque sensors; Barrett "
                   "BH8-280 hand (right) or Schunk SDH2 (left), both with Weiss tactile pads (thesis A.1)")
    arms = (
        Arm("right", "right PA10-7C arm with the Barrett BH8-280 hand", _BARRETT, _BARRETT_SENSORS),
        Arm("left", "left PA10-7C arm with the Schunk SDH2 hand", _SDH2, _SDH2_SENSORS),
    )
    primitives = frozenset({StateType.GRASP, StateType.MOVE, StateType.PUSH, StateType.TRANSPORT,
                            StateType.PLACE, StateType.SLIDE, StateType.RELEASE})
    node_table = (  # thesis Table 7.3
        MappingRow("grasp", "robust_grasp", "pregrasp size", "arm control, FT and tactile sensors"),
        MappingRow("move", "transport", "-", "arm control"),
        MappingRow("push", "transport", "-", "arm control, force-torque sensor (feels the object)"),
        MappingRow("transport", "transport", "obstacles, constraints", "arm control"),
        MappingRow("place", "place", "contact threshold", "arm control, force-torque sensor"),
        MappingRow("slide", "slide", "slide force threshold", "arm control, force-torque sensor"),
        MappingRow("release", "release", "hand position", "arm control"),
    )

    def map_node(self, state: State, context: MappingContext) -> NodeMapping:
        kind = state.type
        if kind is StateType.GRASP:
            return self._grasp(state, context)
        if kind is StateType.RELEASE:
            return self.release(state)
        target, via = self.motion(state, context)
        if kind is StateType.PLACE:
            return NodeMapping("place", self.controller("place", target=target), self.controller("hold_position"))
        if kind is StateType.SLIDE:
            # Thesis 3.3.5: the slide presses with a predefined preshape (a hook on the Barrett).
            shape, notes = self.shape(HandShape.HOOK_GRASP_PRESHAPE)
            return NodeMapping("slide", self.controller("slide", target=target),
                               self.controller("hand_shape", shape=shape.value), notes)
        arm = self.arm_motion(state, target, via, **(obstacle_params(context) if kind is StateType.TRANSPORT else {}))
        if kind is StateType.TRANSPORT:
            # The Barrett's worm drives and the SDH2's position control keep the grasp as it was.
            return NodeMapping("transport", arm, self.controller("hold_position"))
        return NodeMapping("transport", arm, *self.hand_for_motion(state))

    def _grasp(self, state: State, context: MappingContext) -> NodeMapping:
        grasp = state.hand_shape or (_GRASP_OF.get(state.preshape) if state.preshape else None) or DEFAULT_GRASP
        preshape = state.preshape or _PRESHAPE_OF.get(grasp)
        for wanted in (grasp, preshape):
            if wanted in self.arm.hand.cannot_grasp:
                raise Unmappable(f"grasp state '{state.name}' asks for '{wanted.value}': "
                                 f"{self.arm.hand.cannot_grasp[wanted]}",
                                 "use the right arm (--arm right, Barrett hand) or another grasp shape")
        grasp, notes = self.shape(grasp)
        preshape_made, pre_notes = self.shape(preshape) if preshape else (None, ())
        self.check_object_reach(context, grasp.value, *((preshape_made.value,) if preshape_made else ()))
        hand = self.controller("robust_grasp_hand", grasp_shape=grasp.value,
                               preshape=preshape_made.value if preshape_made else None,
                               pregrasp_size=self._pregrasp_size(state, context))
        return NodeMapping("robust_grasp", self.controller("robust_grasp_approach"), hand, notes + pre_notes)

    def _pregrasp_size(self, state: State, context: MappingContext) -> float | None:
        """Table 7.3's extra parameter: how far to open, from the object's size (0..1)."""
        size = state.object_size
        if size is None and context.object is not None and (context.object.size or context.object.object_class):
            size = grasp_width(context.object)
        if size is None:
            return None
        return round(min(1.0, max(0.2, (size + PREGRASP_MARGIN) / self.arm.hand.max_opening)), 3)

    def sensed_event(self, event_type: EventType, origin: State) -> ConditionNode:
        pads = self.arm.sensors_of(SensorKind.TACTILE)
        if event_type is EventType.GRASP_STABLE:
            return self.condition(event_type, "tactile_force_above", _FINGER_PADS, min_pads=2)
        if event_type is EventType.GRASP_LOST:
            return self.condition(event_type, "tactile_force_below", _FINGER_PADS, min_pads=2)
        if event_type is EventType.FINGER_CONTACT:
            return self.condition(event_type, "tactile_force_above", pads, min_pads=1)
        if event_type is EventType.FINGER_CONTACT_LOST:
            return self.condition(event_type, "tactile_force_below", pads, min_pads=1)
        return super().sensed_event(event_type, origin)

