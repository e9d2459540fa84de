"""The control arbitrator (D5 2.2.1, 2.2.4): many controllers' outputs, one robot command.

Arm contributions are velocities, so they blend: the weighted mean of the twists plus the
weighted mean of the joint velocities. Hand contributions are targets, which do not
blend, so per hand DOF the heaviest contribution wins (the later one on a tie).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from primitives.base import ControlData
from primitives.robot import HandMode


@dataclass
class RobotCommand:
    twist: np.ndarray  # (6,) TCP twist, world frame
    joint_velocity: np.ndarray  # (arm_dof,) added after the twist is resolved
    hand_values: np.ndarray | None  # None: no controller drives the hand
    hand_modes: tuple[HandMode, ...]


def _mean(pairs: list[tuple[np.ndarray, float]], size: int) -> np.ndarray:
    total = sum(w for _, w in pairs)
    if not pairs or total <= 0:
        return np.zeros(size)
    return sum(v * w for v, w in pairs) / total


def arbitrate(outputs: list[ControlData], arm_dof: int, hand_dof: int) -> RobotCommand:
    twists = [(np.asarray(o.arm.twist, float), o.arm.weight) for o in outputs if o.arm and o.arm.twist is not None]
    joints = [(np.asarray(o.arm.joint_velocity, float), o.arm.weight)
              for o in outputs if o.arm and o.arm.joint_velocity is not None]
    values = np.full(hand_dof, np.nan)
    modes = [HandMode.VELOCITY] * hand_dof
    best = np.full(hand_dof, -np.inf)
    for out in outputs:
        if out.hand is None:
            continue
        for dof, value in enumerate(out.hand.values):
            if not np.isnan(value) and out.hand.weight >= best[dof]:
                best[dof], values[dof], modes[dof] = out.hand.weight, value, out.hand.modes[dof]
    undriven = np.isnan(values)
    values[undriven] = 0.0  # an undriven DOF is told to stand still
    return RobotCommand(
        twist=_mean(twists, 6),
        joint_velocity=_mean(joints, arm_dof),
        hand_values=None if undriven.all() else values,
        hand_modes=tuple(modes),
    )
