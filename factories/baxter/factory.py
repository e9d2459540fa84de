"""Rethink Baxter (thesis A.4): our own mapping, in the spirit of Tables 7.3 and 7.4.

A 7-DOF compliant arm with a light parallel gripper. It has no tactile pads and its
wrist force-torque sensor is virtual (computed from joint torques): noisy and inaccurate
but good enough for contact detection (A.4). So contact thresholds are raised and the
wrench is low-pass filtered (values in `config.toml`), and a grasp is judged from the
gripper itself (motor force, and jaws stopped before closing fully). The IR range sensor
in the hand judges no grasp: its beam passes through a hollow object (into a cup, through
a roll of tape's core) and reads the table beyond the fingertips while the jaws hold it. It
finds where along the paddles a known object lies before a grasp whose object the task puts
down (`locate_along`): its wrist cannot weigh where the paddles hold it.
"""

from __future__ import annotations

from atd.model.controllers import SensorKind
from atd.model.task import State, Vec3
from atd.model.vocabulary import EventType, HandShape, Movement, StateType
from factories.base import (
    PERCEPTION_ROWS,
    Arm,
    ConditionNode,
    Factory,
    Hand,
    MappingContext,
    MappingRow,
    NodeMapping,
    Sensor,
    all_of,
    obstacle_params,
    PARALLEL_JAW_SHAPES,
    parallel_jaw_closest,
)
from factories.kinds import JAW_UNSCREW_ROW
from factories.turns import leads_into

def _arm(side: str) -> Arm:
    sensors = (
        Sensor("wrist_ft", SensorKind.FORCE_TORQUE,
               "virtual 6-axis wrench computed from joint torques: noisy, for contact detection only"),
        Sensor("gripper", SensorKind.GRIPPER, "gripper jaw opening and motor force"),
        Sensor("ir_range", SensorKind.RANGE, "IR range sensor in the hand, looking along the approach axis"),
    )
    return Arm(side, f"Baxter {side} 7-DOF arm with the light parallel gripper", _GRIPPER, sensors)


_GRIPPER = Hand("Baxter light parallel gripper", "parallel jaw", PARALLEL_JAW_SHAPES,
                parallel_jaw_closest(), max_opening=0.08)


class BaxterFactory(Factory):
    name = "baxter"
    description = ("Rethink Baxter: 7-DOF compliant arms, light parallel gripper, noisy virtual wrist "
                   "force-torque sensor, IR range sensor in the hand; no tactile pads (thesis A.4)")
    arms = (_arm("right"), _arm("left"))
    primitives = frozenset({StateType.GRASP, StateType.MOVE, StateType.PUSH, StateType.TRANSPORT,
                            StateType.PLACE, StateType.SLIDE, StateType.RELEASE,
                            StateType.EXPLORE, StateType.PERCEIVE, StateType.UNSCREW})
    node_table = (
        MappingRow("grasp", "grasp", "grasp force", "arm control, gripper force and opening"),
        MappingRow("move", "move", "-", "arm control, filtered virtual F/T"),
        MappingRow("push", "move", "-", "arm control, filtered virtual F/T (feels the object)"),
        MappingRow("transport", "transport", "obstacles, motion constraints", "arm control, gripper force"),
        MappingRow("place", "place", "contact threshold (raised, filtered)", "arm control, virtual F/T"),
        MappingRow("slide", "slide", "slide force thresholds (raised, filtered)", "arm control, virtual F/T"),
        MappingRow("release", "release", "hand position", "arm control, virtual F/T"),
        *PERCEPTION_ROWS,
        JAW_UNSCREW_ROW,
    )

    def map_node(self, state: State, context: MappingContext) -> NodeMapping:
        kind = state.type
        if kind is StateType.GRASP:
            return self.jaw_grasp(state, context)
        if kind is StateType.RELEASE:
            return self.release(state)
        if kind is StateType.UNSCREW:
            return self.jaw_unscrew(state)
        target, via = self.motion(state, context)
        if kind is StateType.PLACE:
            return NodeMapping("place", self.place(state, context, target), self.controller("squeeze"))
        if kind is StateType.SLIDE:  # press with the closed fingertips
            return NodeMapping("slide", self.controller("slide", target=target),
                               self.controller("hand_shape", shape=HandShape.PINCH_GRASP.value))
        extra = obstacle_params(context) if kind is StateType.TRANSPORT else {}
        arm = self.arm_motion(state, context, self.preshape_target(state, context, target), via, **extra)
        if kind is StateType.TRANSPORT:
            return NodeMapping("transport", arm, self.controller("squeeze"))
        return NodeMapping("move", arm, *self.hand_for_motion(state))

    def preshape_target(self, state: State, context: MappingContext, target: Vec3) -> Vec3:
        """The guarded move straight into the robust grasp, its target left to the object (no
        path), ends with the TCP that grasp's `above_object` over the top of the object the task
        believes in, not at its centre: the grasp's correction makes the descent onto the object
        itself, at 4 cm/s feeling 8 N, where the move came down at 15 cm/s until it felt 30 N,
        and its paddle swept a standing cylinder 6 cm and tipped it over (docs/robust-grasp.md).
        The naive grasp's move goes down as the task says."""
        obj = context.object
        if self.grasp == "naive" or state.type is not StateType.MOVE or state.movement is not Movement.GUARDED \
                or state.path or obj is None or obj.pose is None \
                or leads_into(context.task, state, StateType.GRASP) is None:
            return target
        above = float(self.controller("jaw_grasp_correction").params["above_object"])
        return (target[0], target[1], max(target[2], float(obj.pose.position[2]) + obj.half_height + above))

    def sensed_event(self, event_type: EventType, origin: State) -> ConditionNode:
        gripper = ("gripper",)
        if event_type is EventType.GRASP_STABLE:
            return all_of(self.condition(event_type, "gripper_force_above", gripper),
                          self.condition(event_type, "gripper_opening_above", gripper))
        if event_type is EventType.GRASP_LOST:
            return self.condition(event_type, "gripper_opening_below", gripper)
        if event_type is EventType.FINGER_CONTACT:
            return self.condition(event_type, "gripper_force_above", gripper)
        if event_type is EventType.FINGER_CONTACT_LOST:
            return self.condition(event_type, "gripper_force_below", gripper)
        return super().sensed_event(event_type, origin)
