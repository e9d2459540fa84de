"""Tombatossals, the UJI humanoid torso (thesis A.1): two Mitsubishi PA10-7C arms in one
horizontal plane with a 120 degree aperture, a Barrett BH8-280 hand on the right arm and a
Schunk SDH2 on the left, a JR3 force-torque sensor at each wrist and Weiss tactile pads on
the fingertips. One description is one arm with its hand; the idle arm is left out.

PA10-7C: lengths 317/450/480/70 mm and masses of [PA10SIM]/[CHOR], joint ranges of
[PA10MV] (S2 +-91 deg), joint speeds as recalled in robot-facts.md (1, 2 and 2 pi rad/s;
unverified). Barrett: [BH], [BHFK], [BHWIKI]; SDH2: [SDH] and thesis A.1.2 (210 deg/s).
"""

from __future__ import annotations

from dataclasses import replace
from functools import lru_cache

import numpy as np

from factories.description import FingerPad, Hand, HandDof, Joint, Link, Origin, RobotDescription, SensorModel, Servo, Site
from factories.parts import DARK, METAL, box, capsule, cylinder

D = np.pi / 180

# ---- PA10-7C ---------------------------------------------------------------------------
# (joint, axis, offset from the previous joint along the arm, limit rad, speed rad/s, effort N m, child mass kg, capsule radius)
_PA10 = (
    ("s1", (0, 0, 1), 0.200, 3.089, 1.0, 200.0, 9.78, 0.08),
    ("s2", (0, 1, 0), 0.117, 1.588, 1.0, 200.0, 8.41, 0.07),
    ("s3", (0, 0, 1), 0.200, 3.037, 2.0, 100.0, 3.52, 0.065),
    ("e1", (0, 1, 0), 0.250, 2.391, 2.0, 100.0, 4.31, 0.06),
    ("e2", (0, 0, 1), 0.240, 4.451, 2 * np.pi, 30.0, 3.45, 0.055),
    ("w1", (0, 1, 0), 0.240, 2.880, 2 * np.pi, 30.0, 1.46, 0.05),
    ("w2", (0, 0, 1), 0.040, 4.451, 2 * np.pi, 30.0, 0.24, 0.045),
)
# Length of each link along the arm (to the next joint; w2 to the flange 30 mm, then the JR3).
_LENGTH = (0.117, 0.200, 0.250, 0.240, 0.240, 0.040, 0.030)
JR3_THICKNESS = 0.033
HAND_MOUNT = Origin((0, 0, _LENGTH[-1] + JR3_THICKNESS))  # on w2_link: flange, then the JR3
_SERVO = {
    "s1": (Servo(20000.0, 500.0), 1.0), "s2": (Servo(20000.0, 500.0), 1.0),
    "s3": (Servo(15000.0, 300.0), 0.5), "e1": (Servo(15000.0, 300.0), 0.5),
    "e2": (Servo(6000.0, 60.0), 0.1), "w1": (Servo(6000.0, 60.0), 0.1), "w2": (Servo(6000.0, 60.0), 0.1),
}
# Arm bases on the torso sides, their axes horizontal and 120 degrees apart (60 degrees off
# straight ahead): Ry(90 deg) lays the arm's z horizontal, the yaw turns it out.
_MOUNT = {
    "right": Origin((0.0, -0.12, 0.0), (0.0, np.pi / 2, -np.pi / 3)),
    "left": Origin((0.0, 0.12, 0.0), (0.0, np.pi / 2, np.pi / 3)),
}


def _pa10(side: str) -> tuple[Link, ...]:
    links = [
        Link("torso", None, Origin(), 30.0, (box((0.0, 0.0, 0.0), (0.1, 0.14, 0.25), DARK),)),
        Link("pa10_base", "torso", _MOUNT[side], 3.04, (cylinder((0, 0, 0), (0, 0, 0.2), 0.09, DARK),)),
    ]
    parent = "pa10_base"
    for (name, axis, offset, limit, speed, effort, mass, radius), length in zip(_PA10, _LENGTH):
        servo, armature = _SERVO[name]
        joint = Joint(name, "revolute", axis, -limit, limit, speed, effort, servo, damping=2.0, armature=armature)
        shapes = (capsule((0, 0, 0), (0, 0, length), radius),)
        if name == "w2":  # flange and the JR3 puck
            shapes += (cylinder((0, 0, length), (0, 0, length + JR3_THICKNESS), 0.04, DARK),)
            mass += 0.4
        links.append(Link(f"{name}_link", parent, Origin((0, 0, offset)), mass, shapes, joint))
        parent = f"{name}_link"
    return tuple(links)


# ---- Barrett BH8-280 ------------------------------------------------------------------------
# Palm height Dw 76 mm; spread axes of F1/F2 at x = -+25 mm (Aw), proximal joints 50 mm
# out (A1), proximal link 70 mm (A2), distal 50 mm (A3) bent 42 degrees at rest [BHFK].
# Proximal 0 = finger flat in the palm plane, pointing out; flexion turns it towards the
# approach axis. Distal joint = 0.344 x proximal (TorqueSwitch coupling taken as rigid).
BH_DW, BH_AW, BH_A1, BH_A2, BH_A3 = 0.076, 0.025, 0.050, 0.070, 0.050
BH_DISTAL_REST = 42 * D
BH_COUPLING = 0.84 / 2.44
BH_POINTING = (np.pi / 2 - BH_DISTAL_REST) / (1 + BH_COUPLING)  # proximal flexion that turns the distal link vertical
BH_BOXED_FLEX = 1.3  # rad: pads 12.8 cm apart, 3.5 cm a side to miss the library's widest narrow side (5.7 cm) by
BH_TUCKED = 2.44  # rad: a finger curled fully under the palm, out of a box's way
# The finger drives are self-locking (worm gears): modelled as dry friction on the motor
# joint, so an object pushes a stalled finger back only with more than this (our value).
BH_SELF_LOCK = 0.5
_BH_FINGER = Servo(kp=20.0, kv=0.3)  # kv also limits the free closing speed under force to about 2 rad/s
_BH_SPREAD = Servo(kp=20.0, kv=1.0)


def _barrett_finger(finger: str, parent: str, origin: Origin) -> tuple[tuple[Link, ...], FingerPad]:
    flex = (0.0, -1.0, 0.0)  # about -y: x (along the finger) turns towards +z (the approach side)
    proximal = Link(
        f"bh_{finger}_proximal", parent, origin, 0.1, (box((0.035, 0, 0), (0.035, 0.012, 0.009), METAL),),
        Joint(f"bh_{finger}_proximal", "revolute", flex, 0.0, 2.44, 2.0, 3.0, _BH_FINGER, damping=0.05, armature=0.01,
              friction=BH_SELF_LOCK),
    )
    distal = Link(
        f"bh_{finger}_distal", proximal.name, Origin((BH_A2, 0, 0), (0, -BH_DISTAL_REST, 0)), 0.05,
        (box((0.023, 0, 0), (0.023, 0.011, 0.007), METAL),),  # the pad owns the last 4 mm
        Joint(f"bh_{finger}_distal", "revolute", flex, 0.0, 0.84, 2.0 * BH_COUPLING, 1.0, _BH_FINGER, damping=0.02, armature=0.005),
    )
    # Weiss pad on the grasping (+z) face of the distal link, 5 x 8 taxels (thesis A.1.2),
    # flush with the fingertip: a small object is touched by the pad's tip edge.
    pad = FingerPad(f"tactile_{finger}", distal.name, Origin((0.031, 0, 0.0085)), (0.019, 0.012), 0.003, (5, 8))
    return (proximal, distal), pad


def _barrett() -> tuple[tuple[Link, ...], Hand, float]:
    links: list[Link] = [
        Link("bh_palm", "w2_link", HAND_MOUNT, 0.6,
             (box((0, 0, BH_DW / 2), (0.045, 0.065, BH_DW / 2), DARK),), com=(0, 0, 0.037)),
    ]
    pads = []
    for finger, x, axis in (("f1", -BH_AW, 1.0), ("f2", BH_AW, -1.0)):
        knuckle = Link(
            f"bh_{finger}_knuckle", "bh_palm", Origin((x, 0, BH_DW), (0, 0, np.pi / 2)), 0.05,
            (box((0.025, 0, 0.008), (0.03, 0.012, 0.008), METAL),),
            Joint(f"bh_{finger}_spread", "revolute", (0, 0, axis), 0.0, np.pi, 1.0, 2.0, _BH_SPREAD, damping=0.05, armature=0.01),
        )
        chain, pad = _barrett_finger(finger, knuckle.name, Origin((BH_A1, 0, 0)))
        links += [knuckle, *chain]
        pads.append(pad)
    chain, pad = _barrett_finger("f3", "bh_palm", Origin((0, -BH_A1, BH_DW), (0, 0, -np.pi / 2)))
    links += chain
    pads.append(pad)
    # Weiss 6 x 14 pad on the palm (thesis A.1.2), its columns across the palm.
    pads.append(FingerPad("tactile_palm", "bh_palm", Origin((0, 0, BH_DW + 0.0015)), (0.035, 0.015), 0.003, (6, 14)))

    def finger(name: str) -> HandDof:
        return HandDof(name, ((f"bh_{name}_proximal", 1.0), (f"bh_{name}_distal", BH_COUPLING)), 1, 0.0, 2.44, geared=True)

    dofs = (
        HandDof("spread", (("bh_f1_spread", 1.0), ("bh_f2_spread", 1.0)), 0, 0.0, 0.0),
        finger("f1"), finger("f2"), finger("f3"),
    )
    # D5 hand shapes the Barrett can make (D5 3.2, Miller et al.): (spread, f1, f2, f3).
    postures = {
        "open": (0.0, 0.0, 0.0, 0.0),
        "extend": (0.0, 0.0, 0.0, 0.0),
        "closed": (0.0, 2.44, 2.44, 2.44),
        "power_grasp_preshape": (0.0, 0.6, 0.6, 0.6),
        "power_grasp": (0.0, 2.0, 2.0, 2.0),
        "cylindrical_grasp_preshape": (0.0, 0.6, 0.6, 0.6),
        "cylindrical_grasp": (0.0, 2.0, 2.0, 2.0),
        "spherical_grasp_preshape": (np.pi / 3, 0.6, 0.6, 0.6),
        "spherical_grasp": (np.pi / 3, 2.0, 2.0, 2.0),
        "pinch_grasp_preshape": (np.pi / 2, 0.6, 0.6, 0.0),
        "pinch_grasp": (np.pi / 2, 1.6, 1.6, 0.0),
        # The pinch inside a box (`boxed`): F3 curled under the palm (it stays 2.9 cm over the
        # TCP) and F1 and F2 flexed further, pads 12.8 cm apart: it spans 20.5 x 13 cm from
        # above, where the pinch preshape's 28.2 x 22.4 cm fits no 28 x 23 cm box inside.
        "boxed_pinch_grasp_preshape": (np.pi / 2, BH_BOXED_FLEX, BH_BOXED_FLEX, BH_TUCKED),
        "boxed_pinch_grasp": (np.pi / 2, 1.6, 1.6, BH_TUCKED),
        "hook_grasp_preshape": (np.pi, 0.8, 0.8, 0.8),
        "hook_grasp": (np.pi, 1.6, 1.6, 1.6),
        # To push: F3 points down, its distal link vertical so that every face of it is, and
        # F1 and F2 curl into fists 4 cm above its tip, clear of the object.
        "push": (0.0, 2.44, 2.44, BH_POINTING),
    }
    # A 5 cm box is pinched between F1 and F2 spread to face each other (F3 stays flat): two
    # equal, opposed fingers balance under a fixed effort where F1+F2 against F3 would not.
    # The push acts on F3's distal link, out along hand -y.
    pointing = (0.0, -(BH_A1 + BH_A2 * np.cos(BH_POINTING)), 0.0)
    # The pinch's sliding grasp does not follow the table down: kept on it, F1's and F2's tips
    # slide under an object's bottom edge as they curl and lift one side (docs/constants.md).
    # From the side, a quarter turn about the approach axis: the pinch's F1 and F2, facing
    # each other along hand x, close across a standing bottle instead of on its top and
    # bottom, and F3, flat in the pinch, stands up off the table instead of 7 cm into it.
    # Its pinch's pads meet a cap tip first, their faces turned 68 degrees up off its side: 2 mm
    # over the task's depth, a lug cap rising 2.5 mm up its thread stays on the tips (docs/unscrew-campaign.md).
    hand = Hand("barrett_bh8_280", dofs, tuple(pads), postures, test_grasp="pinch_grasp", pinch_clearance=0.002,
                grasp_centres={"push": pointing}, push_posture="push", rising_grasps=frozenset({"pinch_grasp"}),
                side_roll=-np.pi / 2,  # the object's friction: rubber pads kept its finger-lost correction from moving a 5 kg box (PyBullet; docs/slide.md)
                boxed={"pinch_grasp_preshape": "boxed_pinch_grasp_preshape", "pinch_grasp": "boxed_pinch_grasp"})
    return tuple(links), hand, 0.155


# ---- Schunk SDH2 --------------------------------------------------------------------------
# Finger bases 74.5 mm above the palm frame: finger 1 (19, +33) mm, finger 2 (19, -33) mm,
# thumb (-38, 0) mm; knuckle 16.5 mm, proximal 86.5 mm, distal 68.5 mm (unconfirmed) [SDH].
# Flexion 0 = straight out along the approach axis; positive curls the finger inwards.
SDH_BASE_Z, SDH_KNUCKLE, SDH_PROXIMAL, SDH_DISTAL = 0.0745, 0.0165, 0.0865, 0.0685
SDH_FINGER_X, SDH_FINGER_Y, SDH_THUMB_X = 0.019, 0.033, -0.038
SDH_TIP_HALF_WIDTH = 0.011  # m: its pad spans it; 2 mm bare strips each side met objects off the pinch line unfelt (docs/robust-grasp.md)
_SDH_SERVO = Servo(kp=30.0, kv=1.0)
_SDH_SPEED = 210 * D  # thesis A.1.2


def _sdh_finger(finger: str, parent: str, origin: Origin, pad_name: str | None = None) -> tuple[tuple[Link, ...], FingerPad]:
    curl = (0.0, 1.0, 0.0)  # about +y: z (along the finger) turns towards +x (inwards)
    proximal = Link(
        f"sdh_{finger}_proximal", parent, origin, 0.15,
        (box((0, 0, SDH_PROXIMAL / 2), (0.01, 0.0125, SDH_PROXIMAL / 2), METAL),),
        Joint(f"sdh_{finger}_proximal", "revolute", curl, -np.pi / 2, np.pi / 2, _SDH_SPEED, 2.0, _SDH_SERVO,
              damping=0.05, armature=0.01),
    )
    distal = Link(
        f"sdh_{finger}_distal", proximal.name, Origin((0, 0, SDH_PROXIMAL)), 0.1,
        (box((0, 0, SDH_DISTAL / 2), (0.009, SDH_TIP_HALF_WIDTH, SDH_DISTAL / 2), METAL),),
        Joint(f"sdh_{finger}_distal", "revolute", curl, -np.pi / 2, np.pi / 2, _SDH_SPEED, 1.4, _SDH_SERVO,
              damping=0.05, armature=0.01),
    )
    # Weiss pad on the inner (+x) face of the distal link, 6 x 13 taxels, edge to edge across
    # it; Ry(90 deg) turns the pad's normal to +x and its x down the finger.
    pad = FingerPad(pad_name or f"tactile_{finger}", distal.name, Origin((0.0105, 0, 0.038), (0, np.pi / 2, 0)),
                    (0.024, SDH_TIP_HALF_WIDTH), 0.003, (6, 13))
    return (proximal, distal), pad


def _sdh2() -> tuple[tuple[Link, ...], Hand, float]:
    links: list[Link] = [
        Link("sdh_palm", "w2_link", HAND_MOUNT, 1.1,
             (cylinder((0, 0, 0), (0, 0, SDH_BASE_Z), 0.05, DARK),)),
    ]
    pads = []
    for finger, y, axis in (("f1", SDH_FINGER_Y, 1.0), ("f2", -SDH_FINGER_Y, -1.0)):
        knuckle = Link(
            f"sdh_{finger}_knuckle", "sdh_palm", Origin((SDH_FINGER_X, y, SDH_BASE_Z), (0, 0, np.pi)), 0.05,
            (cylinder((0, 0, 0), (0, 0, SDH_KNUCKLE), 0.014, METAL),),
            Joint(f"sdh_{finger}_rotation", "revolute", (0, 0, axis), 0.0, np.pi / 2, 80 * D, 2.0, _SDH_SERVO,
                  damping=0.05, armature=0.01),
        )
        chain, pad = _sdh_finger(finger, knuckle.name, Origin((0, 0, SDH_KNUCKLE)))
        links += [knuckle, *chain]
        pads.append(pad)
    chain, pad = _sdh_finger("thumb", "sdh_palm", Origin((SDH_THUMB_X, 0, SDH_BASE_Z + SDH_KNUCKLE)), pad_name="tactile_f3")
    links += chain
    pads.append(pad)

    def joint(name: str) -> HandDof:
        return HandDof(name, ((f"sdh_{name}", 1.0),), 1, -0.5 if name.endswith("proximal") else 0.5, 1.2)

    dofs = (HandDof("rotation", (("sdh_f1_rotation", 1.0), ("sdh_f2_rotation", 1.0)), 0, 0.0, 0.0),) + tuple(
        joint(f"{f}_{p}") for f in ("f1", "f2", "thumb") for p in ("proximal", "distal")
    )

    def shape(rotation: float, proximal: float, distal: float, thumb: bool = True) -> tuple[float, ...]:
        t = (proximal, distal) if thumb else (-0.5, 0.5)
        return (rotation, proximal, distal, proximal, distal) + t

    # D5 hand shapes the SDH2 can make; its 90 degree rotation cannot make a hook (thesis
    # A.1.2). Grasps close the proximal joints and keep the fingertips' angle, so the
    # tactile pads meet the object face on.
    postures = {
        "open": shape(0.0, -0.5, 0.5),
        "extend": shape(0.0, 0.0, 0.0),
        "closed": shape(0.0, 1.2, 1.2),
        "power_grasp_preshape": shape(0.0, -0.3, 0.3),
        "power_grasp": shape(0.0, 0.6, 0.3),
        "cylindrical_grasp_preshape": shape(0.0, -0.3, 0.3),
        "cylindrical_grasp": shape(0.0, 0.6, 0.3),
        "spherical_grasp_preshape": shape(np.pi / 3, -0.3, 0.3),
        "spherical_grasp": shape(np.pi / 3, 0.6, 0.3),
        "pinch_grasp_preshape": shape(np.pi / 2, -0.3, 0.3, thumb=False),
        "pinch_grasp": shape(np.pi / 2, 0.5, 0.3, thumb=False),
        # To push: the thumb straight down, every face of it vertical, the fingers curled
        # up into fists 11 cm above its tip, clear of the object.
        "push": (0.0, 1.2, 1.2, 1.2, 1.2, 0.0, 0.0),
    }
    # The pinch closes the two fingers, turned to face each other, on the line through their
    # bases, 19 mm off the TCP (the thumb's side of the palm is empty); the three-finger
    # grasps close on the TCP, the centre of the circle the three fingers stand on.
    pinch = (SDH_FINGER_X, 0.0, 0.0)
    # The push acts on the thumb's axis.
    centres = {"pinch_grasp_preshape": pinch, "pinch_grasp": pinch, "push": (SDH_THUMB_X, 0.0, 0.0)}
    # Three fingers 120 degrees apart balance each other on a small box.
    hand = Hand("schunk_sdh2", dofs, tuple(pads), postures, test_grasp="spherical_grasp", grasp_centres=centres,
                push_posture="push", side_edge_pinch=True)  # the object's friction: rubber pads held the jam jar's neck against the unscrew's pull (docs/slide.md)
    return tuple(links), hand, 0.225


# ---- the robot ---------------------------------------------------------------------------------
# Found with `inverse_kinematics` from many starts, keeping the solution farthest from
# the joint limits: TCP 15 cm above the middle of the work area, top-down.
HOME = {
    "right": (2.0532, 0.9389, -0.4985, 1.7014, 1.9358, -1.3386, -1.6889),
    "left": (1.502, -0.8841, -0.1818, -1.6711, -1.648, 1.7894, -1.5213),
}
# Where an arm waits while the other works: its hand top-down at home height, 30 cm from
# the middle towards its own shoulder, clear of a 5-10 cm object the other lifts 15 cm over
# the middle (Baxter's, whose left gripper a cylinder lifted from home met, are the same).
PARK = {"right": (0.125, -0.30, 0.15), "left": (0.125, 0.30, 0.15)}


ARMS = ("right", "left")  # what `description(arm)` accepts (None = the first); its factory's arm names


@lru_cache(maxsize=None)
def description(arm: str | None = None) -> RobotDescription:
    side = arm or ARMS[0]
    if side not in ARMS:
        raise ValueError(f"Tombatossals has a 'left' (Schunk SDH2) and a 'right' (Barrett) arm; got '{arm}'")
    hand_links, hand, tcp_depth = _barrett() if side == "right" else _sdh2()
    root = hand_links[0].name
    d = RobotDescription(
        name="tombatossals",
        payload=10.0,  # kg, PA10: 'payload 10 kg'
        arm=side,
        links=_pa10(side) + hand_links,
        arm_joints=tuple(row[0] for row in _PA10),
        hand_root=root,
        hand=hand,
        tcp=Site("tcp", root, Origin((0, 0, tcp_depth))),
        wrist_sensor=Site("wrist_ft", root),
        # Torso behind the table, the arms' plane 35 cm above the table top.
        base=Origin((-0.5, 0.0, 0.35)),
        home=HOME[side],
        park=PARK[side],
        sensors={
            "joints": SensorModel(resolution=1e-5),
            # JR3: no public datasheet; a few hundredths of a newton (robot-facts.md section 6).
            "wrench": SensorModel(noise_std=(0.05, 0.05, 0.05, 0.002, 0.002, 0.002)),
            "tactile": SensorModel(resolution=0.01),
        },
        extra_sites=(Site("attachment_site", "w2_link", HAND_MOUNT),),
    )
    if side == "left":
        return d
    # The Barrett's hook hangs its three fingers 8 cm to one side of its TCP: it presses (a
    # slide, thesis 3.3.5) and is placed with its fingertips, not with the empty TCP.
    return replace(d, hand=replace(hand, grasp_centres={**hand.grasp_centres, "hook_grasp_preshape": _tips(d, "hook_grasp_preshape")}))


def _tips(d: RobotDescription, posture: str) -> tuple[float, float, float]:
    """Where the fingers' tips are in a posture, TCP frame: across, the centre of the finger
    pads; along the approach, the hand's reach."""
    poses = d.link_poses(d.hand_joint_targets(np.asarray(d.hand.postures[posture], float)))
    to_hand = np.linalg.inv(poses[d.tcp.link] @ d.tcp.origin.matrix())
    pads = [to_hand @ poses[p.link] @ p.origin.matrix() for p in d.hand.pads if p.link != d.hand_root]
    x, y = np.mean([pad[:2, 3] for pad in pads], axis=0)
    return (round(float(x), 4), round(float(y), 4), round(d.hand_reach(posture), 4))
