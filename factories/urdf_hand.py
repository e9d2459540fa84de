"""What a URDF does not say about a parallel gripper, added from what it does: the grip DOF
from its two finger joints, a tactile pad on each fingertip's inner face, and the TCP
between the pads. The hand's z axis is taken as its approach axis, as URDF grippers have it.
"""

from __future__ import annotations

import numpy as np

from atd.model.frames import rpy_of
from factories.description import FingerPad, Hand, HandDof, Link, Origin, Site
from factories.urdf import UrdfError, UrdfModel

PAD_LENGTH = 0.02  # m along the finger: a fingertip pad
PAD_THICKNESS = 0.002  # m
TAXEL_PITCH = 0.0034  # m, as the Weiss pads of the built-in robots


def _finger_pad(finger: Link, hand_root: str, pad_name: str, hand_in_finger: np.ndarray) -> tuple[FingerPad, float]:
    """The pad on the finger's closing face at its tip, and the pad centre's depth along hand z.

    The box that bounds the finger's first shape along the finger's axes gives the face:
    the side the joint's closing direction (-axis) points to; the pad spans the box across,
    `PAD_LENGTH` along the approach, ending at the fingertip."""
    if not finger.shapes:
        raise UrdfError(f"finger link '{finger.name}' has no collision geometry to put a pad on; "
                        "give it a <collision> in the URDF")
    low, high = finger.shapes[0].bounds()
    extent = (high - low) / 2  # half extents along the finger link's axes
    centre = (high + low) / 2
    closing = -np.asarray(finger.joint.axis, float)
    approach = hand_in_finger[:3, 2]  # hand z in the finger's frame
    across = np.cross(approach, closing)
    tip = float(centre @ approach + extent @ np.abs(approach))
    # The pad stands proud of the finger by its thickness, so an object touches the pad, not the finger.
    face = centre + closing * (float(extent @ np.abs(closing)) + PAD_THICKNESS)
    surface = face + approach * (tip - PAD_LENGTH / 2 - float(face @ approach))
    frame = np.column_stack([across, approach, closing])  # pad x across, y along to the tip, z out of the face
    half_across = float(extent @ np.abs(across))
    taxels = (max(1, round(PAD_LENGTH / TAXEL_PITCH)), max(1, round(2 * half_across / TAXEL_PITCH)))
    pad = FingerPad(pad_name, finger.name, Origin(tuple(float(v) for v in surface), rpy_of(frame)),  # type: ignore[arg-type]
                    (half_across, PAD_LENGTH / 2), PAD_THICKNESS, taxels)
    tip_in_hand = np.linalg.inv(hand_in_finger) @ np.append(surface, 1.0)
    return pad, float(tip_in_hand[2])


def urdf_parallel_jaw(model: UrdfModel, hand_root: str, fingers: tuple[str, str],
                      pad_names: tuple[str, str] = ("tactile_left", "tactile_right")) -> tuple[Hand, Site]:
    """The hand model of a gripper whose two finger joints (prismatic, opening with their
    value) hang from `hand_root`, with a pad on each fingertip; and the TCP between the pads."""
    links = {link.joint.name: link for link in model.links if link.joint is not None}
    missing = [f for f in fingers if f not in links]
    if missing:
        raise UrdfError(f"{model.path}: has no moving joint '{missing[0]}'; its joints: {', '.join(links)}")
    pads, depths = [], []
    for joint, pad_name in zip(fingers, pad_names):
        finger = links[joint]
        if finger.joint.kind != "prismatic" or finger.parent != hand_root:
            raise UrdfError(f"{model.path}: joint '{joint}' is not a prismatic joint on '{hand_root}'; a parallel jaw "
                            "has two, one per finger")
        pad, depth = _finger_pad(finger, hand_root, pad_name, np.linalg.inv(finger.origin.matrix()))
        pads.append(pad)
        depths.append(depth)
    left, right = (links[f].joint for f in fingers)
    grip = HandDof("grip", ((left.name, 1.0), (right.name, 1.0)), -1, left.upper, left.lower)
    open_, closed = (left.upper,), (left.lower,)
    hand = Hand(name=f"{hand_root}_gripper", dofs=(grip,), pads=tuple(pads),
                postures={"open": open_, "closed": closed, "pinch_grasp_preshape": open_, "pinch_grasp": closed,
                          "power_grasp_preshape": open_, "power_grasp": closed})
    return hand, Site("tcp", hand_root, Origin((0.0, 0.0, float(np.mean(depths)))))
