"""Rethink Baxter: one 7-DOF arm with its electric parallel gripper, the noisy virtual wrist
force-torque sensor and the wrist IR range sensor (thesis A.4).

Joint origins, limits, efforts and link masses are those of [BAX] (robot-facts.md
section 7), the newer xacro where the two disagree; velocity limits are the URDF's. The
real Baxter has no tactile pads: each finger "pad" reports the grip force the gripper
measures (its motor effort), as the real gripper does, and has no taxel array.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from factories.description import RUBBER, Hand, Joint, Link, Origin, RobotDescription, SensorModel, Servo, Site
from factories.parts import DARK, JawSpec, box, capsule, parallel_jaw

PI2 = np.pi / 2

# (joint, origin xyz, origin rpy, lower, upper, velocity, effort, child mass, child CoM) [BAX]
_ARM = (
    ("s0", (0.055695, 0, 0.011038), (0, 0, 0), -1.70168, 1.70168, 1.5, 50.0, 5.70044, (0.01783, 0.00086, 0.19127)),
    ("s1", (0.069, 0, 0.27035), (-PI2, 0, 0), -2.147, 1.047, 1.5, 50.0, 3.22698, (0.06845, 0.00269, -0.00529)),
    ("e0", (0.102, 0, 0), (PI2, 0, PI2), -3.05418, 3.05418, 1.5, 50.0, 4.31272, (-0.00276, 0.00132, 0.18086)),
    ("e1", (0.069, 0, 0.26242), (-PI2, -PI2, 0), -0.05, 2.618, 1.5, 50.0, 2.07206, (0.02611, 0.00159, -0.01117)),
    ("w0", (0.10359, 0, 0), (PI2, 0, PI2), -3.059, 3.059, 4.0, 15.0, 2.24665, (-0.00168, 0.0046, 0.13952)),
    ("w1", (0.01, 0, 0.2707), (-PI2, -PI2, 0), -1.5708, 2.094, 4.0, 15.0, 1.60979, (0.06041, 0.00697, 0.006)),
    ("w2", (0.115975, 0, 0), (PI2, 0, PI2), -3.059, 3.059, 4.0, 15.0, 0.35093, (0.00198, 0.00125, 0.01855)),
)
# Each link's capsule runs from its joint to the next joint's origin; radii are our estimate of the shells.
_RADIUS = (0.07, 0.06, 0.055, 0.05, 0.045, 0.045, 0.04)
_NEXT = tuple(row[1] for row in _ARM[1:]) + ((0, 0, 0.11355),)  # w2 -> hand [BAX]
_SHOULDER = Servo(kp=5000.0, kv=200.0)
_WRIST = Servo(kp=1000.0, kv=20.0)

# Electric gripper [BAX rethink_ee_description]: extended narrow fingers (112.7 mm) with
# paddle tips (42 x 6.5 x 37 mm), 20.8 mm travel per finger; finger slots chosen so the
# 41.7 mm of travel spans a 26-68 mm opening, wide enough for the 5-6 cm class defaults.
GRIPPER = JawSpec(
    prefix="gripper",
    pad_prefix="gripper",
    body_half=(0.03, 0.05, 0.01),
    body_mass=0.3,
    finger_base_z=0.02,
    finger_half=(0.00675, 0.005, 0.05635),
    finger_mass=0.03,
    stroke=0.020833,
    gap_closed=0.026,
    pad_half=(0.021, 0.0185),
    pad_thickness=0.0065,
    taxels=None,
    effort=20.0,
    velocity=0.1,
    servo=Servo(kp=3000.0, kv=40.0),
)

HAND_MOUNT = Origin((0, 0, 0.025))  # gripper base on the hand link (electric-gripper xacro) [BAX]
# Found with `inverse_kinematics`: TCP 15 cm above the middle of the work area, top-down.
HOME = {
    "right": (0.5567, -0.6607, 0.9944, 1.9396, 2.1332, -0.8987, -1.8344),
    "left": (-0.5567, -0.6607, -0.9944, 1.9396, -2.1332, -0.8987, 1.8344),  # the right one mirrored
}
# Where an arm waits while the other works: its hand top-down at home height, 30 cm from
# the middle towards its own shoulder, clear of a 5-10 cm object the other lifts 15 cm over
# the middle (Baxter's left gripper held a cylinder its right arm lifted into it from home).
PARK = {"right": (0.125, -0.30, 0.15), "left": (0.125, 0.30, 0.15)}


def _arm(side: str) -> tuple[Link, ...]:
    sign = 1.0 if side == "left" else -1.0
    links = [
        Link("torso", None, Origin(), 35.336, (box((0, 0, 0.3), (0.14, 0.18, 0.3), DARK),)),
        # Pedestal column down to the floor, 0.93 m below the base frame [BAXSIM].
        Link("pedestal", "torso", Origin(), 60.864, (capsule((0, 0, -0.9), (0, 0, -0.1), 0.12, DARK),)),
        Link("arm_mount", "torso", Origin((0.024645, sign * 0.219645, 0.118588), (0, 0, sign * 0.7854)), 0.1),
    ]
    parent = "arm_mount"
    for (name, xyz, rpy, lo, hi, vel, effort, mass, com), radius, end in zip(_ARM, _RADIUS, _NEXT):
        big = name in ("s0", "s1", "e0", "e1")
        joint = Joint(name, "revolute", (0, 0, 1), lo, hi, vel, effort, _SHOULDER if big else _WRIST,
                      damping=0.5, armature=0.3 if big else 0.05)
        links.append(Link(f"{name}_link", parent, Origin(xyz, rpy), mass, (capsule((0, 0, 0), end, radius),), joint, com=com))
        parent = f"{name}_link"
    links.append(Link("hand", parent, Origin((0, 0, 0.11355)), 0.19125, (box((0, 0, 0.0125), (0.035, 0.035, 0.0125), DARK),),
                      com=(0.01093, 0.00042, -0.01532)))
    return tuple(links)


ARMS = ("right", "left")  # what `description(arm)` accepts (None = the first); its factory's arm names


@lru_cache(maxsize=None)
def description(arm: str | None = None) -> RobotDescription:
    side = arm or ARMS[0]
    if side not in ARMS:
        raise ValueError(f"Baxter has a 'left' and a 'right' arm; got '{arm}'")
    hand_links, grip, pads, tcp_depth = parallel_jaw(GRIPPER, "hand", HAND_MOUNT)
    hand = Hand(
        name="electric_gripper",
        dofs=(grip,),
        pads=pads,
        postures={
            "open": (GRIPPER.stroke,),
            "closed": (0.0,),
            "pinch_grasp_preshape": (GRIPPER.stroke,),
            "pinch_grasp": (0.0,),
            "power_grasp_preshape": (GRIPPER.stroke,),
            "power_grasp": (0.0,),
        },
        pad_force_from_effort=True,
        surface_friction=RUBBER,  # rubber fingertip inserts
    )
    return RobotDescription(
        name="baxter",
        payload=2.2,  # kg, Rethink's figure, end effector included
        arm=side,
        links=_arm(side) + hand_links,
        arm_joints=tuple(row[0] for row in _ARM),
        hand_root="gripper_base",
        hand=hand,
        tcp=Site("tcp", "gripper_base", Origin((0, 0, tcp_depth))),
        wrist_sensor=Site("wrist_ft", "gripper_base"),
        # Base frame 0.93 m above the floor [BAXSIM], table top about 0.78 m: 0.15 m above
        # the table, far enough back for the pedestal to clear the table's edge.
        base=Origin((-0.40, 0.0, 0.15)),
        home=HOME[side],
        park=PARK[side],
        sensors={
            "joints": SensorModel(resolution=0.0004),  # about 14-bit encoders
            # Estimated from joint torques: noisy, coarse, slightly biased (thesis A.4).
            "wrench": SensorModel(noise_std=(1.0, 1.0, 1.0, 0.08, 0.08, 0.08), bias=(0.1, 0.1, 0.1, 0.01, 0.01, 0.01),
                                  cutoff_hz=20.0, resolution=0.1),
            "tactile": SensorModel(resolution=0.1),  # the gripper's force reading
            "range": SensorModel(noise_std=0.002, resolution=0.001),
        },
        # As on the real hand, the IR sensor looks out of the gripper's centre along the approach
        # axis, from the face between the finger roots: a held object sits in its beam.
        range_sensor=Site("ir_range", "gripper_base", Origin((0, 0, 2 * GRIPPER.body_half[2]))),
        range_limits=(0.04, 0.40),
        extra_sites=(Site("attachment_site", "hand", HAND_MOUNT),),
    )
