"""The Franka Emika Panda with the Franka Hand: what translation knows of it, and how tasks map onto it.

Made by `atd robots new panda --from-urdf` on pybullet_data's franka_panda/panda.urdf, then
tuned: the names users know it by, the pads and wrist sensor it was given (the real Panda
estimates the wrench at its flange from its joint torque sensors; here it has a 6-axis sensor
between flange and hand, and a tactile pad on each fingertip).

It extends `ParallelJawFactory`, which maps a parallel-jaw robot as the Melfa is mapped in
thesis Table 7.4 (grasp closes until both pads feel the grasp force, transport squeezes,
place stops on the change of load the pads feel, no slide).
To map something differently, override `map_node` (primitives), `sensed_event` (events from
the sensors) or `success`, and call `super()` for the rest; `node_table` (what `atd robots
show` prints as the mapping table) is the thesis table it inherits, until you set your own.
"""

from __future__ import annotations

from atd.robot_api import (
    PARALLEL_JAW_SHAPES,
    Arm,
    Hand,
    ParallelJawFactory,
    Sensor,
    SensorKind,
    parallel_jaw_closest,
)

from atd_panda.description import MAX_OPENING, description

HAND = Hand("Franka Hand", "parallel jaw", PARALLEL_JAW_SHAPES, parallel_jaw_closest(), max_opening=MAX_OPENING)
# The names of the sensors are those of the description's pads and wrist sensor site.
LEFT, RIGHT = (pad.name for pad in description().hand.pads)
SENSORS = (
    Sensor("wrist_ft", SensorKind.FORCE_TORQUE, "6-axis force-torque sensor between the flange and the Franka Hand"),
    Sensor(LEFT, SensorKind.TACTILE, "tactile pad on the left fingertip"),
    Sensor(RIGHT, SensorKind.TACTILE, "tactile pad on the right fingertip"),
)


class PandaFactory(ParallelJawFactory):
    name = "panda"
    description = ("Franka Emika Panda 7-DOF arm with a wrist force-torque sensor and the Franka Hand parallel "
                   "gripper with a tactile pad on each fingertip (body from pybullet_data's panda.urdf)")
    arms = (Arm("main", "Panda arm with the Franka Hand", HAND, SENSORS),)
