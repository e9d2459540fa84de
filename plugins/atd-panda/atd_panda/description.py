"""The Franka Emika Panda's body, read from its URDF: the one description both simulators
are built from.

`read_urdf` takes the links, joints, limits, masses, inertias and collision geometry from
the installed pybullet_data's franka_panda/panda.urdf;
what a URDF lacks is added here: the gripper's grip, a tactile pad on each fingertip and
the TCP between them (`urdf_parallel_jaw`), the wrist force-torque sensor where the hand
is fixed to the arm, the sensors' noise, where the robot stands and its home posture.
The drives' gains, damping and armature come from each joint's effort limit; to tune a
joint, replace its `Joint` in `model.links` (dataclasses.replace) before building the robot.
"""

from __future__ import annotations

from functools import lru_cache
from importlib.resources import files
from pathlib import Path

from atd.robot_api import (
    Origin,
    RobotDescription,
    SensorModel,
    Site,
    read_urdf,
    urdf_parallel_jaw,
)

# Read from the installed `pybullet_data` package, never copied.
URDF = Path(str(files("pybullet_data") / "franka_panda/panda.urdf"))
ARM_JOINTS = ('panda_joint1', 'panda_joint2', 'panda_joint3', 'panda_joint4', 'panda_joint5', 'panda_joint6', 'panda_joint7')  # base to flange
HAND_ROOT = "panda_hand"  # where the wrist force-torque sensor measures
FINGERS = ('panda_finger_joint1', 'panda_finger_joint2')  # prismatic, opening with their value
MAX_OPENING = 0.08  # m between the fingers, fully open
# Behind the table, facing along world x, its base level with the table top, set back by 0.4
# of the arm's summed joint offsets (45 cm for the Panda): the work area then lies mid-reach.
BASE = Origin((-0.444, 0.0, 0.0))
# TCP 15 cm above the middle of the work area, hand pointing down: found by `with_home(robot)`
# when this file was written; find it again after changing the links or BASE.
HOME = (0.0598, 0.3171, -0.06, -2.1505, 0.0299, 2.4668, -2.3768)


@lru_cache(maxsize=None)
def description(arm: str | None = None) -> RobotDescription:
    """The robot with its one arm, 'main' (None means it too)."""
    if arm not in (None, "main"):
        raise ValueError(f"the panda has one arm, 'main'; got arm '{arm}' (leave --arm out)")
    model = read_urdf(URDF)
    hand, tcp = urdf_parallel_jaw(model, HAND_ROOT, FINGERS)
    return RobotDescription(
        name="panda",
        arm=None,
        links=model.links,
        arm_joints=ARM_JOINTS,
        hand_root=HAND_ROOT,
        hand=hand,
        tcp=tcp,
        wrist_sensor=Site("wrist_ft", HAND_ROOT),
        base=BASE,
        home=HOME,
        sensors={
            "joints": SensorModel(resolution=1e-5),
            "wrench": SensorModel(noise_std=(0.05, 0.05, 0.05, 0.002, 0.002, 0.002)),
            "tactile": SensorModel(resolution=0.01),
        },
    )
