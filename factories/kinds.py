"""Mappings shared by every robot of a kind, so a new robot declares what it has and inherits
how its primitives and events are mapped.

`ParallelJawFactory`: one arm with a wrist force-torque sensor and a two-jaw gripper with a
tactile pad on each jaw, mapped as the Melfa is in thesis Table 7.4: grasp closes until the
pads feel the grasp force, transport keeps squeezing, release opens the jaws with the arm
still, and there is no slide. Place is not Table 7.4's transport but the place primitive
(thesis Eq. 3.4, felt on the wrist): it weighs where the jaws hold the object and puts the
object, not the TCP, on the target (a box held 2.5 cm along the jaws was set down 2.5 cm off).

`MultiFingerFactory`: one arm with a wrist force-torque sensor and a hand with tactile pads
on its fingers, mapped as Tombatossals is in thesis Table 7.3: the robust grasp (preshape
opened to the object, close, adapt the force), place and slide felt on the wrist sensor,
release backing off the surface, and the hand kept as it is while the arm carries.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from atd.model.controllers import SensorKind
from atd.model.task import State
from atd.model.vocabulary import EventType, HandShape, StateType
from factories.base import (PERCEPTION_ROWS, ConditionNode, Factory, MappingContext, MappingRow, NodeMapping, Unmappable,
                            grasp_width, holding_force, obstacle_params, refuse_uncarriable)

# The grasp a hand closes into when the task names none, and the preshape that precedes each grasp.
DEFAULT_GRASP = HandShape.POWER_GRASP
PRESHAPE_OF = {
    HandShape.POWER_GRASP: HandShape.POWER_GRASP_PRESHAPE,
    HandShape.PINCH_GRASP: HandShape.PINCH_GRASP_PRESHAPE,
    HandShape.CYLINDRICAL_GRASP: HandShape.CYLINDRICAL_GRASP_PRESHAPE,
    HandShape.SPHERICAL_GRASP: HandShape.SPHERICAL_GRASP_PRESHAPE,
    HandShape.HOOK_GRASP: HandShape.HOOK_GRASP_PRESHAPE,
}
GRASP_OF = {pre: grasp for grasp, pre in PRESHAPE_OF.items()}
PREGRASP_MARGIN = 0.04  # m of clearance around the object when the hand preshapes (ours)
SWING_MARGIN = 0.005  # m the sliding grasp may back off beyond the fingertips' swing (ours)
SIDE_MARGIN = 0.01  # m a grasp from the side may go past where the task believes the object's axis (ours)
# Thesis 3.3.6 on a gripper (ours): the jaws grip the cap, the last wrist joint twists it.
JAW_UNSCREW_ROW = MappingRow("unscrew", "unscrew", "grasp force, twist angle (of the last wrist joint), torque and "
                             "pull limits", "arm control, FT sensor, gripper force")


class ParallelJawFactory(Factory):
    """A parallel-jaw robot as in thesis Table 7.4; its tactile sensors are the two jaws' pads."""

    primitives = frozenset({StateType.GRASP, StateType.MOVE, StateType.PUSH, StateType.TRANSPORT,
                            StateType.PLACE, StateType.RELEASE,
                            StateType.EXPLORE, StateType.PERCEIVE, StateType.UNSCREW})
    node_table = (  # thesis Table 7.4
        MappingRow("grasp", "grasp", "grasp force", "arm control, tactile sensors"),
        MappingRow("move", "move", "-", "arm control"),
        MappingRow("push", "move", "-", "arm control, force-torque sensor (feels the object)"),
        MappingRow("transport", "transport", "motion constraints", "arm control, tactile"),
        MappingRow("place", "place", "contact threshold", "arm control, force-torque sensor"),
        MappingRow("slide", "-", "-", "-"),
        MappingRow("release", "release", "hand position", "arm control"),
        *PERCEPTION_ROWS,
        JAW_UNSCREW_ROW,
    )
    lacks = {StateType.SLIDE: ("the {name} has no slide primitive (a parallel jaw maps as thesis Table 7.4)",
                               "push the object instead (type=\"push\"), or translate for a robot that slides")}

    def map_node(self, state: State, context: MappingContext) -> NodeMapping:
        kind = state.type
        if kind is StateType.UNSCREW:
            return self.jaw_unscrew(state)
        if kind is StateType.GRASP:
            return self.jaw_grasp(state, context)
        if kind is StateType.RELEASE:  # Table 7.4: a hand position only, the arm stays
            return self.release(state, arm="hold")
        target, via = self.motion(state, context)
        if kind is StateType.PLACE:  # the place primitive, which weighs where the jaws hold the object
            return NodeMapping("place", self.place(state, context, target), self.controller("squeeze"))
        arm = self.arm_motion(state, context, target, via)
        if kind is StateType.TRANSPORT:
            return NodeMapping("transport", arm, self.controller("squeeze"))
        return NodeMapping("move", arm, *self.hand_for_motion(state))

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


class MultiFingerFactory(Factory):
    """A multi-finger robot as in thesis Table 7.3. A grasp is stable when two of its
    `holding_pads` press (a palm pad may touch without holding); any pad is a contact."""

    primitives = frozenset({StateType.GRASP, StateType.MOVE, StateType.PUSH, StateType.TRANSPORT,
                            StateType.PLACE, StateType.SLIDE, StateType.RELEASE,
                            StateType.EXPLORE, StateType.PERCEIVE, StateType.UNSCREW})
    node_table = (  # thesis Table 7.3
        MappingRow("grasp", "robust_grasp", "pregrasp size", "arm control, FT and tactile sensors"),
        MappingRow("move", "transport", "-", "arm control"),
        MappingRow("push", "transport", "-", "arm control, force-torque sensor (feels the object)"),
        MappingRow("transport", "transport", "obstacles, constraints", "arm control"),
        MappingRow("place", "place", "contact threshold", "arm control, force-torque sensor"),
        MappingRow("slide", "slide", "slide force threshold", "arm control, force-torque sensor"),
        MappingRow("release", "release", "hand position", "arm control"),
        *PERCEPTION_ROWS,
        MappingRow("unscrew", "unscrew", "grasp force, twist angle, torque and pull limits",
                   "arm control, FT and tactile sensors"),
    )
    holding_pads: ClassVar[tuple[str, ...]] = ()  # empty: every tactile sensor holds
    refused_grasp_hint: ClassVar[str] = "use another grasp shape"

    def map_node(self, state: State, context: MappingContext) -> NodeMapping:
        kind = state.type
        if kind is StateType.GRASP:
            return self.finger_grasp(state, context)
        if kind is StateType.RELEASE:
            return self.release(state)
        if kind is StateType.UNSCREW:
            return self.unscrew(state)
        target, via = self.motion(state, context)
        if kind is StateType.PLACE:
            return NodeMapping("place", self.place(state, context, target), self.controller("hold_position"))
        if kind is StateType.SLIDE:
            # Thesis 3.3.5: the slide presses with a predefined preshape (a hook on the Barrett),
            # its path for where that preshape presses (`shape_offset`), as the move before it.
            shape, notes = self.shape(HandShape.HOOK_GRASP_PRESHAPE)
            target, _ = self.motion(state.model_copy(update={"hand_shape": HandShape.HOOK_GRASP_PRESHAPE}), context)
            return NodeMapping("slide", self.controller("slide", target=target),
                               self.controller("hand_shape", shape=shape.value), notes)
        extra = obstacle_params(context) if kind is StateType.TRANSPORT else {}
        arm = self.arm_motion(state, context, target, via, **extra)
        if kind is StateType.TRANSPORT:  # the fingers keep the grasp as it was
            return NodeMapping("transport", arm, self.controller("hold_position"))
        return NodeMapping("transport", arm, *self.hand_for_motion(state, context))

    def finger_grasp(self, state: State, context: MappingContext) -> NodeMapping:
        """The robust grasp (thesis 3.3.1): the state's grasp, or the one its preshape leads
        to, or a power grasp; refused when the hand cannot make it or would hit an obstacle."""
        grasp, preshape_made, notes = self.grasp_shapes(state, self.grasp_of(state))
        closed = self.boxed(grasp.value, context)
        placed = self.boxed(preshape_made.value, context) if preshape_made else closed
        self.check_object_reach(context, state, closed, *((placed,) if preshape_made else ()))
        configured = float(self.controller("robust_grasp_hand").params["grasp_force"])
        refuse_uncarriable(context.object, f"grasp state '{state.name}'")
        needed = holding_force(context.object)
        edges = {"side_edge_correction": True} if self.robot.hand.side_edge_pinch else None
        swing = self.robot.closing_swing(placed, closed)
        hand = self.controller("robust_grasp_hand", edges, grasp_shape=closed,
                               preshape=placed if preshape_made else None,
                               pregrasp_size=self.pregrasp_size(state, context),
                               grasp_force=round(needed, 3) if needed > configured else None,
                               closing_swing=round(swing, 6))
        rising = grasp.value in self.robot.hand.rising_grasps
        extent, offset = self.footprint(placed)
        arm = self.controller("robust_grasp_approach", {"follow_surface": False} if rising else None,
                              max_distance=self.side_travel(state, context),
                              wrist_to_tcp=round(self._wrist_to_tcp, 6),
                              fingertip_reach=round(max(self.robot.hand_reach(placed), 0.001), 6),
                              max_back_off=round(swing + SWING_MARGIN, 6),
                              hand_extent=tuple(round(e, 6) for e in extent),
                              hand_offset=tuple(round(o, 6) for o in offset),
                              grasp_centre=tuple(round(float(c), 6) for c in
                                                 self.robot.hand.grasp_centres.get(closed, (0.0, 0.0, 0.0))))
        return NodeMapping("robust_grasp", arm, hand, notes)

    def grasp_of(self, state: State) -> HandShape:
        """The grasp a grasp state asks for: its own, or the one its preshape leads to, or a power grasp."""
        return state.hand_shape or (GRASP_OF.get(state.preshape) if state.preshape else None) or DEFAULT_GRASP

    def grasp_postures(self, state: State) -> tuple[str, str]:
        """The postures the robust grasp's hand closes from and to: its preshape (or open) to its grasp."""
        grasp, preshape_made, _ = self.grasp_shapes(state, self.grasp_of(state))
        return (preshape_made or HandShape.OPEN).value, grasp.value

    def unscrew(self, state: State) -> NodeMapping:
        """Thesis 3.3.6: the state's grasp (by default a two-finger pinch, GRASPING_FINGERS 2)
        on the cap, opened to `object_size` (the cap's width) when the state gives it; the
        pads' lower edge there (`pinch_reach`) is where the move before put them (but for the
        hand's `pinch_clearance`), and where the hand keeps them on a narrower cap (`pad_reach`)."""
        grasp, preshape_made, notes = self.grasp_shapes(state, state.hand_shape or HandShape.PINCH_GRASP)
        reach = None if state.object_size is None or preshape_made is None else \
            self.robot.pinch_reach(preshape_made.value, grasp.value, state.object_size)
        hand = self.controller("unscrew_hand", grasp_shape=grasp.value, pregrasp_size=self.opening(state.object_size),
                               preshape=preshape_made.value if preshape_made else None,
                               cap_width=state.object_size, pad_reach=None if reach is None else round(reach, 6))
        centre = self.robot.hand.grasp_centres.get(grasp.value, (0.0, 0.0, 0.0))
        arm = self.controller("unscrew_arm", grasp_centre=tuple(round(float(c), 6) for c in centre),
                              wrist_turn=self.wrist_turn(state))
        return NodeMapping("unscrew", arm, hand, notes)

    def grasp_shapes(self, state: State, grasp: HandShape) -> tuple[HandShape, HandShape | None, tuple[str, ...]]:
        """The grasp and the preshape (the state's, or the grasp's own) the hand makes for
        them, with notes on shapes only approximated; refused when it cannot make one."""
        preshape = state.preshape or PRESHAPE_OF.get(grasp)
        for wanted in (grasp, preshape):
            if wanted in self.arm.hand.cannot_grasp:
                raise Unmappable(f"{state.type.value} state '{state.name}' asks for '{wanted.value}': "
                                 f"{self.arm.hand.cannot_grasp[wanted]}", self.refused_grasp_hint)
        made, notes = self.shape(grasp)
        preshape_made, pre_notes = self.shape(preshape) if preshape else (None, ())
        return made, preshape_made, notes + pre_notes

    def side_travel(self, state: State, context: MappingContext) -> float | None:
        """How far a grasp from the side approaches: until its grasp centre has passed the
        object's axis by SIDE_MARGIN. From above the support stops the fingertips; from the
        side nothing does, and an SDH2, its fingers open around a bottle 4 cm wide, went on
        the whole `max_distance` until its knuckles pushed the bottle, its grasp centre 13 cm
        beyond it (issue 32). None (the default) for a grasp from above."""
        if context.object is None or context.object.pose is None:
            return None
        centre = np.asarray(context.object.pose.position, float)
        rotation, line, from_above = self._grasp_line(context, state, centre)
        if from_above:
            return None
        return round(max(0.0, float((centre - line) @ rotation[:, 2])) + SIDE_MARGIN, 6)

    def pregrasp_size(self, state: State, context: MappingContext) -> float | None:
        """Table 7.3's extra parameter: how far to open, from the object's size (0..1)."""
        size = state.object_size
        if size is None and context.object is not None and (context.object.size or context.object.object_class):
            size = grasp_width(context.object)
        return self.opening(size)

    def opening(self, size: float | None) -> float | None:
        """How far to open (0..1) around an object `size` wide, with PREGRASP_MARGIN; None for no size."""
        if size is None:
            return None
        return round(min(1.0, max(0.2, (size + PREGRASP_MARGIN) / self.arm.hand.max_opening)), 3)

    def sensed_event(self, event_type: EventType, origin: State) -> ConditionNode:
        pads = self.arm.sensors_of(SensorKind.TACTILE)
        holding = self.holding_pads or pads
        if event_type is EventType.GRASP_STABLE:
            return self.condition(event_type, "tactile_force_above", holding, min_pads=2)
        if event_type is EventType.GRASP_LOST:
            return self.condition(event_type, "tactile_force_below", holding, min_pads=2)
        if event_type is EventType.FINGER_CONTACT:
            return self.condition(event_type, "tactile_force_above", pads, min_pads=1)
        if event_type is EventType.FINGER_CONTACT_LOST:
            return self.condition(event_type, "tactile_force_below", pads, min_pads=1)
        return super().sensed_event(event_type, origin)
