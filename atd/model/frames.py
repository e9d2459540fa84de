"""Rotations in the convention every layer shares (URDF's fixed-axis roll, pitch, yaw), and
the gravity of the world frame they turn in (z up)."""

from __future__ import annotations

from functools import lru_cache
from typing import Sequence

import numpy as np

GRAVITY = 9.81  # m/s^2, along the world's -z


def rotation_rpy(rpy: Sequence[float]) -> np.ndarray:
    """URDF fixed-axis roll, pitch, yaw (radians): R = Rz(yaw) Ry(pitch) Rx(roll)."""
    r, p, y = rpy
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    return np.array(
        [
            [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr],
        ]
    )


def rpy_of(r: np.ndarray) -> tuple[float, float, float]:
    """URDF roll, pitch, yaw of a rotation matrix (the inverse of `rotation_rpy`)."""
    pitch = np.arctan2(-r[2, 0], np.hypot(r[0, 0], r[1, 0]))
    if abs(np.cos(pitch)) < 1e-9:  # gimbal lock: put everything in yaw
        return (0.0, float(pitch), float(np.arctan2(-r[0, 1], r[1, 1])))
    return (float(np.arctan2(r[2, 1], r[2, 2])), float(pitch), float(np.arctan2(r[1, 0], r[0, 0])))


def rotation_angle(rotation: np.ndarray) -> float:
    """The angle of a rotation matrix, in degrees."""
    cos = (float(np.trace(rotation)) - 1.0) / 2.0
    return float(np.degrees(np.arccos(max(-1.0, min(1.0, cos)))))


def axis_rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rodrigues' rotation about a unit axis."""
    k, kk = _cross_matrix(*(float(v) for v in axis))
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * kk


@lru_cache(maxsize=1024)
def _cross_matrix(x: float, y: float, z: float) -> tuple[np.ndarray, np.ndarray]:
    """The axis's cross-product matrix K and K @ K, made once per axis (forward kinematics
    turns about each joint's own axis over and over), read-only."""
    k = np.array([[0, -z, y], [z, 0, -x], [-y, x, 0]])
    kk = k @ k
    k.flags.writeable = kk.flags.writeable = False
    return k, kk


def rectangle_corners(half_size: tuple[float, float]) -> np.ndarray:
    """The four corners of a rectangle of `half_size` (x, y) centred in its own frame's z = 0
    plane, (4, 4) homogeneous rows: a pad's sensing surface, ready for its pose's transform."""
    hx, hy = half_size
    return np.array([[sx * hx, sy * hy, 0.0, 1.0] for sx in (-1.0, 1.0) for sy in (-1.0, 1.0)])
