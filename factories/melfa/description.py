"""Mitsubishi Melfa RV-3SB with a Weiss WRT-102 gripper (a Schunk PG70 with tactile fingers)
and a JR3 wrist force-torque sensor (thesis A.3).

Kinematics from the standard DH table of [RV3SB] (robot-facts.md section 4), rewritten as
joint origins: at zero the upper arm stands vertical and the forearm points forward along
world x. Joint ranges and speeds from [RV3SB]; the arm weighs 37 kg (thesis A.3), spread
over the links by their size (our choice). Gripper numbers from [PG70U] (section 5).
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from factories.description import Hand, Joint, Link, Origin, RobotDescription, SensorModel, Servo, Site
from factories.parts import DARK, JawSpec, capsule, cylinder, parallel_jaw

D = np.pi / 180

# (name, axis, lower, upper, speed deg/s, effort N m): effort limits are not published;
# chosen from the 3 kg payload at full reach with margin.
_JOINTS = (
    ("j1", (0, 0, 1), -170, 170, 250, 150.0),
    ("j2", (0, 1, 0), -90, 135, 187, 150.0),
    ("j3", (0, 1, 0), -20, 171, 250, 100.0),  # range flagged unverified in robot-facts.md
    ("j4", (1, 0, 0), -160, 160, 412, 30.0),
    ("j5", (0, 1, 0), -120, 120, 412, 30.0),
    ("j6", (1, 0, 0), -360, 360, 660, 20.0),
)
_BIG = Servo(kp=6000.0, kv=250.0)
_WRIST = Servo(kp=1500.0, kv=40.0)

# The PG70 body (80 x 100 x 93 mm), its fingers (30 x 10 x 60 mm) carrying a Weiss
# DSA-style 6 x 14 taxel pad (3.4 mm pitch), 34 mm stroke per jaw [PG70U].
PG70 = JawSpec(
    prefix="pg70",
    pad_prefix="tactile",
    body_half=(0.04, 0.05, 0.0465),
    body_mass=1.2,
    finger_base_z=0.093,
    finger_half=(0.015, 0.0035, 0.03),
    finger_mass=0.1,
    stroke=0.034,
    gap_closed=0.0,
    pad_half=(0.0102, 0.0238),
    pad_thickness=0.003,
    taxels=(14, 6),
    effort=100.0,  # per jaw: about 200 N of grip, the catalogue figure (unconfirmed)
    velocity=0.0415,  # per jaw: 83 mm/s opening speed of the PG70 driver
    servo=Servo(kp=20000.0, kv=300.0),
)

# The gripper on the flange, past the JR3: Ry(90 deg) turns the hand's z (approach) along link6's x.
HAND_MOUNT = Origin((0.03, 0, 0), (0, np.pi / 2, 0))
# Found with `inverse_kinematics`: TCP 15 cm above the middle of the work area (0.125, 0), top-down.
HOME = (0.0, -0.0187, 0.8227, 0.0, 0.7667, 0.0)


def _arm() -> tuple[Link, ...]:
    spec = {name: Joint(name, "revolute", axis, lo * D, hi * D, v * D, e, _BIG if name in ("j1", "j2", "j3") else _WRIST,
                        damping=1.0, armature=0.5 if name in ("j1", "j2", "j3") else 0.05)
            for name, axis, lo, hi, v, e in _JOINTS}
    return (
        Link("base", None, Origin(), 8.0, (cylinder((0, 0, 0), (0, 0, 0.18), 0.085, DARK),)),
        Link("link1", "base", Origin(), 8.0,
             (cylinder((0, 0, 0.18), (0, 0, 0.33), 0.07), capsule((0, 0, 0.35), (0.095, 0, 0.35), 0.06)),
             spec["j1"], com=(0.02, 0, 0.28)),
        Link("link2", "link1", Origin((0.095, 0, 0.35)), 6.0, (capsule((0, 0, 0), (0, 0, 0.245), 0.05),), spec["j2"]),
        Link("link3", "link2", Origin((0, 0, 0.245)), 4.0, (capsule((0, 0, 0), (0, 0, 0.135), 0.045),), spec["j3"]),
        Link("link4", "link3", Origin((0, 0, 0.135)), 2.5, (capsule((0, 0, 0), (0.27, 0, 0), 0.04),), spec["j4"]),
        Link("link5", "link4", Origin((0.27, 0, 0)), 1.2, (capsule((0, 0, 0), (0.05, 0, 0), 0.035),), spec["j5"]),
        # Flange plus the JR3 puck (30 mm, about 0.3 kg).
        Link("link6", "link5", Origin((0.085, 0, 0)), 0.5, (cylinder((0, 0, 0), (0.03, 0, 0), 0.04, DARK),), spec["j6"]),
    )


ARMS = ("main",)  # what `description(arm)` accepts (None = the first); its factory's arm names


@lru_cache(maxsize=None)
def description(arm: str | None = None) -> RobotDescription:
    if arm not in (None, *ARMS):
        raise ValueError(f"the Melfa has one arm, 'main'; got arm '{arm}' (leave --arm out)")
    hand_links, grip, pads, tcp_depth = parallel_jaw(PG70, "link6", HAND_MOUNT)
    hand = Hand(
        name="wrt102",
        dofs=(grip,),
        pads=pads,
        postures={
            "open": (PG70.stroke,),
            "closed": (0.0,),
            "pinch_grasp_preshape": (PG70.stroke,),
            "pinch_grasp": (0.0,),
            "power_grasp_preshape": (PG70.stroke,),
            "power_grasp": (0.0,),
        },
        # The object's friction alone (no rubber, unlike the hands that slide; docs/constants.md).
    )
    return RobotDescription(
        name="melfa",
        payload=3.0,  # kg, RV-3SB: the 3 in its name
        arm=None,
        links=_arm() + hand_links,
        arm_joints=tuple(j[0] for j in _JOINTS),
        hand_root="pg70_base",
        hand=hand,
        tcp=Site("tcp", "pg70_base", Origin((0, 0, tcp_depth))),
        wrist_sensor=Site("wrist_ft", "pg70_base"),
        # On its stand behind the table, base plate 10 cm below the table top. Level with it, a
        # top-down grasp at the work area's middle put the wrist in its singularity (j5 = 0
        # at the object's centre height): the forearm and flange rolls swung against each
        # other, j4 hit its limit, and descents drifted 8 mm sideways. Here j5 is 0.3 rad or
        # more all over the work area's floor, and its corners stay reachable top-down.
        base=Origin((-0.25, 0.0, -0.1)),
        home=HOME,
        sensors={
            "joints": SensorModel(resolution=1e-5),
            # JR3-class: a few hundredths of a newton of noise (no datasheet found; robot-facts.md section 6).
            "wrench": SensorModel(noise_std=(0.05, 0.05, 0.05, 0.002, 0.002, 0.002)),
            "tactile": SensorModel(noise_std=0.0, resolution=0.01),
        },
        extra_sites=(Site("attachment_site", "link6", HAND_MOUNT),),
    )
