"""The Franka Emika Panda's body, read from its URDF: the one description both simulators
are built from.

`read_urdf` takes the links, joints, limits, masses, inertias, collision and visual meshes
from the installed pybullet_data's franka_panda/panda.urdf; that file's inertias are
placeholders (0.1 kg m^2 about every axis of every link), so the arm's links get the
published identified ones instead (`IDENTIFIED`), and the hand and fingers Franka's (`HAND`). What a URDF lacks is added here: the
gripper's grip, a tactile pad on each fingertip and the TCP between them
(`urdf_parallel_jaw`), the wrist force-torque sensor where the hand is fixed to the arm,
the sensors' noise, where the robot stands and its home posture.
The drives' gains, damping and reflected rotor inertia come from each joint's effort
limit; to tune a joint, replace its `Joint` in `model.links` (dataclasses.replace) before
building the robot. The arm's rotor inertia is carried by the link it turns (`_rotor_in_link`).
"""

from __future__ import annotations

from dataclasses import replace
from functools import lru_cache
from importlib.resources import files
from pathlib import Path

import numpy as np

from atd.robot_api import (
    Link,
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
# The arm's links as identified on a real Panda: mass (kg), centre of mass (m) and inertia
# about it (kg m^2; ixx, iyy, izz, then ixy, ixz, iyz), in the link frames of the URDF, which
# are those of the paper's modified Denavit-Hartenberg convention. From C. Gaz, M. Cognetti,
# A. Oliva, P. Robuffo Giordano, A. De Luca, "Dynamic Identification of the Franka Emika
# Panda Robot With Retrieval of Feasible Parameters Using Penalty-Based Optimization",
# IEEE RA-L 4(4), 2019, supplementary material tables VIII and IX, as the authors list
# them in github.com/marcocognetti/FrankaEmikaPandaDynModel (DynPars2VREP.m). Link 1's
# centre of mass lies on joint 1's axis at a height the identification cannot see: 0 there.
IDENTIFIED = {
    "panda_link1": (4.970684, (3.875e-03, 2.081e-03, 0.0),
                    (7.0337e-01, 7.0661e-01, 9.1170e-03), (-1.3900e-04, 6.7720e-03, 1.9169e-02)),
    "panda_link2": (0.646926, (-3.141e-03, -2.872e-02, 3.495e-03),
                    (7.9620e-03, 2.8110e-02, 2.5995e-02), (-3.9250e-03, 1.0254e-02, 7.0400e-04)),
    "panda_link3": (3.228604, (2.7518e-02, 3.9252e-02, -6.6502e-02),
                    (3.7242e-02, 3.6155e-02, 1.0830e-02), (-4.7610e-03, -1.1396e-02, -1.2805e-02)),
    "panda_link4": (3.587895, (-5.317e-02, 1.04419e-01, 2.7454e-02),
                    (2.5853e-02, 1.9552e-02, 2.8323e-02), (7.7960e-03, -1.3320e-03, 8.6410e-03)),
    "panda_link5": (1.225946, (-1.1953e-02, 4.1065e-02, -3.8437e-02),
                    (3.5549e-02, 2.9474e-02, 8.6270e-03), (-2.1170e-03, -4.0370e-03, 2.2900e-04)),
    "panda_link6": (1.666555, (6.0149e-02, -1.4117e-02, -1.0517e-02),
                    (1.9640e-03, 4.3540e-03, 5.4330e-03), (1.0900e-04, -1.1580e-03, 3.4100e-04)),
    "panda_link7": (7.35522e-01, (1.0517e-02, -4.252e-03, 6.1597e-02),
                    (1.2516e-02, 1.0027e-02, 4.8150e-03), (-4.2800e-04, -1.1960e-03, -7.4100e-04)),
}
# The hand and fingers, which the paper leaves out, as Franka Emika give them in franka_ros
# (franka_description/robots/common/inertial.yaml, in the same link frames): the hand 0.73 kg
# (the URDF says 0.81) with its centre of mass 3 cm up from the flange, each finger 15 g (the
# URDF: 100 g), in place of the URDF's 0.1 kg m^2 about every axis, a hundred times the hand's
# real inertia. That file puts a finger's centre of mass at its joint, below the finger; the
# URDF's, 2 cm up inside the finger's mesh, is kept.
HAND = {
    "panda_hand": (0.73, (-0.01, 0.0, 0.03), (1.0e-3, 2.5e-3, 1.7e-3), (0.0, 0.0, 0.0)),
    "panda_leftfinger": (0.015, (0.0, 0.01, 0.02), (2.375e-6, 2.375e-6, 7.5e-7), (0.0, 0.0, 0.0)),
    "panda_rightfinger": (0.015, (0.0, -0.01, 0.02), (2.375e-6, 2.375e-6, 7.5e-7), (0.0, 0.0, 0.0)),
}
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
    links = tuple(_rotor_in_link(_published(link)) for link in model.links)
    hand, tcp = urdf_parallel_jaw(model, HAND_ROOT, FINGERS)
    return RobotDescription(
        name="panda",
        arm=None,
        links=links,
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


def _published(link: Link) -> Link:
    """The link with its published mass and inertia (IDENTIFIED, HAND) in place of the URDF's."""
    if link.name not in IDENTIFIED | HAND:
        return link
    mass, com, moments, products = (IDENTIFIED | HAND)[link.name]
    return replace(link, mass=mass, com=com, inertia=moments, inertia_products=products)


def _rotor_in_link(link: Link) -> Link:
    """The link carrying its joint's reflected rotor inertia as a disk about the joint axis,
    its joint without armature: PyBullet has no armature, and with only the light identified
    links 1 and 2 between them, joints 1 and 3 (on one axis when joint 2 is at 0) traded
    speed in Bullet until joint 3 ran at 163% of its limit (`atd robots test panda --engine
    pybullet`, measured). MuJoCo then sees the same rotor as a body, not as armature."""
    if link.joint is None or link.joint.name not in ARM_JOINTS or link.joint.kind != "revolute":
        return link
    rotor, axis = link.joint.armature, np.asarray(link.joint.axis, float)
    tensor = np.diag(link.inertia_diagonal) + rotor / 2 * (np.eye(3) + np.outer(axis, axis))
    products = np.asarray(link.inertia_products, float) + rotor / 2 * np.array(
        [axis[0] * axis[1], axis[0] * axis[2], axis[1] * axis[2]])
    return replace(link, inertia=tuple(float(v) for v in np.diag(tensor)),
                   inertia_products=tuple(float(v) for v in products), joint=replace(link.joint, armature=0.0))
