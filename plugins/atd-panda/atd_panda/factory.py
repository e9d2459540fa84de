"""The panda factory: what translation knows of the robot, and how tasks map onto it.

It extends `ParallelJawFactory`, which maps a parallel-jaw robot as the Melfa is mapped in
thesis Table 7.4 (grasp closes until both pads feel the grasp force, transport squeezes,
place stops on the change of load the pads feel, no slide).
To map something differently, override `map_node` (primitives), `sensed_event` (events from
the sensors) or `success`, and call `super()` for the rest.
"""

from __future__ import annotations

from atd.robot_api import (
    PARALLEL_JAW_SHAPES,
    Arm,
    Hand,
    MappingRow,
    ParallelJawFactory,
    Sensor,
    SensorKind,
    parallel_jaw_closest,
)

from atd_panda.description import MAX_OPENING, description

HAND = Hand("panda gripper", "parallel jaw", PARALLEL_JAW_SHAPES, parallel_jaw_closest(), max_opening=MAX_OPENING)
# The names of the sensors are those of the description's pads and wrist sensor site.
LEFT, RIGHT = (pad.name for pad in description().hand.pads)
SENSORS = (
    Sensor("wrist_ft", SensorKind.FORCE_TORQUE, "6-axis force-torque sensor between arm and gripper"),
    Sensor(LEFT, SensorKind.TACTILE, "tactile pad on the left jaw"),
    Sensor(RIGHT, SensorKind.TACTILE, "tactile pad on the right jaw"),
)


class PandaFactory(ParallelJawFactory):
    name = "panda"
    description = "a 6-DOF arm with a wrist force-torque sensor and a parallel gripper with tactile pads"
    arms = (Arm("main", "the panda arm with its gripper", HAND, SENSORS),)
    node_table = (  # what `atd robots show panda` prints, in the columns of thesis Table 7.4
        MappingRow("grasp", "grasp", "grasp force", "arm control, tactile sensors"),
        MappingRow("move", "move", "-", "arm control"),
        MappingRow("push", "move", "-", "arm control, force-torque sensor (feels the object)"),
        MappingRow("transport", "transport", "motion constraints", "arm control, tactile"),
        MappingRow("place", "transport", "motion constraints", "arm control, tactile"),
        MappingRow("slide", "-", "-", "-"),
        MappingRow("release", "release", "hand position", "arm control"),
    )
