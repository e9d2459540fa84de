"""Building blocks shared by the robot descriptions: shapes between two points and the
two-jaw parallel gripper used (with different numbers) by the Melfa and Baxter."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from factories.description import (
    FingerPad,
    HandDof,
    Joint,
    Link,
    Origin,
    Servo,
    Shape,
    Vec3,
)

METAL = (0.55, 0.57, 0.6, 1.0)
DARK = (0.2, 0.2, 0.22, 1.0)
PAD = (0.85, 0.45, 0.1, 1.0)


def capsule(p0: Vec3, p1: Vec3, radius: float, rgba=METAL) -> Shape:
    """A capsule whose axis runs from p0 to p1 (link frame)."""
    return _along("capsule", p0, p1, radius, rgba)


def cylinder(p0: Vec3, p1: Vec3, radius: float, rgba=METAL) -> Shape:
    """A cylinder whose axis runs from p0 to p1 (link frame)."""
    return _along("cylinder", p0, p1, radius, rgba)


def _along(kind, p0: Vec3, p1: Vec3, radius: float, rgba) -> Shape:
    a, b = np.asarray(p0, float), np.asarray(p1, float)
    d = b - a
    length = float(np.linalg.norm(d))
    u = d / length
    pitch = float(np.arccos(np.clip(u[2], -1.0, 1.0)))
    yaw = float(np.arctan2(u[1], u[0])) if pitch > 1e-9 else 0.0
    centre = tuple(float(v) for v in (a + b) / 2)
    return Shape(kind, (radius, length / 2), Origin(centre, (0.0, pitch, yaw)), rgba)


def box(centre: Vec3, half: Vec3, rgba=METAL, rpy: Vec3 = (0.0, 0.0, 0.0)) -> Shape:
    """A box with its centre and half extents in the link frame, turned by `rpy`."""
    return Shape("box", half, Origin(centre, rpy), rgba)


@dataclass(frozen=True)
class JawSpec:
    """A two-jaw parallel gripper: a body, then two mirrored prismatic fingers along y.

    Lengths in metres from the mounting face (the wrist sensor's face): the finger
    joints sit `finger_base_z` out; `gap_closed` is the pad-to-pad gap at joint
    position 0 and `stroke` the travel of each jaw.
    """

    prefix: str
    """Of its link and joint names."""
    pad_prefix: str
    """Of its pads' names: `<pad_prefix>_left` and `_right`."""
    body_half: Vec3
    """Half extents of the gripper body, m."""
    body_mass: float
    """kg."""
    finger_base_z: float
    """Distance from the mounting face to the finger joints, m."""
    finger_half: Vec3
    """Finger box half extents (x across, y thickness, z along), m."""
    finger_mass: float
    """kg, each."""
    stroke: float
    """Travel of each jaw, m."""
    gap_closed: float
    """Pad-to-pad gap with the jaws at 0, m."""
    pad_half: tuple[float, float]
    """(across, along) half extents of the pad surface, m."""
    pad_thickness: float
    """m."""
    taxels: tuple[int, int] | None
    """(rows along the finger, cols across), or None for one force per pad."""
    effort: float
    """Force limit per jaw, N."""
    velocity: float
    """Speed limit per jaw, m/s."""
    servo: Servo
    """The jaws' servo."""


def parallel_jaw(spec: JawSpec, parent: str, mount: Origin) -> tuple[tuple[Link, ...], HandDof, tuple[FingerPad, ...], float]:
    """Links, the one grip DOF (= opening of each jaw), the pads and the TCP depth.

    Pad frames: z = outward normal of the sensing surface, x across the finger,
    y along it (towards the fingertip), so taxel rows run across and columns along.
    """
    p = spec.prefix
    fx, fy, fz = spec.finger_half
    pad_centre_z = 2 * fz - spec.pad_half[1]  # pad flush with the fingertip
    links = [
        Link(
            f"{p}_base",
            parent,
            mount,
            spec.body_mass,
            (box((0, 0, spec.body_half[2]), spec.body_half, DARK),),
        )
    ]
    pads = []
    for side, sign in (("left", 1.0), ("right", -1.0)):
        finger = f"{p}_{side}_finger"
        joint = Joint(
            f"{p}_{side}_jaw", "prismatic", (0.0, sign, 0.0), 0.0, spec.stroke, spec.velocity, spec.effort, spec.servo,
            damping=5.0, armature=0.05,
        )
        inner = sign * spec.gap_closed / 2  # inner face of the pad at q = 0
        body_y = inner + sign * (spec.pad_thickness + fy)
        shapes = (
            box((0, body_y, fz), (fx, fy, fz), METAL),
        )
        links.append(Link(finger, f"{p}_base", Origin((0, 0, spec.finger_base_z)), spec.finger_mass, shapes, joint))
        # Rx(90 deg) turns the pad's z to -y (the left pad looks at the right one) and its
        # y up the finger; the right pad is the same turned half round the finger axis.
        pads.append(
            FingerPad(
                f"{spec.pad_prefix}_{side}",
                finger,
                Origin((0.0, inner, pad_centre_z), (np.pi / 2, 0.0, 0.0 if sign > 0 else np.pi)),
                spec.pad_half,
                spec.pad_thickness,
                spec.taxels,
            )
        )
    dof = HandDof("grip", ((f"{p}_left_jaw", 1.0), (f"{p}_right_jaw", 1.0)), -1, spec.stroke, 0.0)
    return tuple(links), dof, tuple(pads), spec.finger_base_z + pad_centre_z
