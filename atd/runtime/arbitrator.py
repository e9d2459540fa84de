"""The control arbitrator (D5 2.2.1, 2.2.4): many controllers' outputs, one robot command.

Arm contributions are velocities, so they blend: the weighted mean of the twists plus the
weighted mean of the joint velocities. Hand contributions are targets, which do not
blend, so per hand DOF the heaviest contribution wins (the later one on a tie).

It runs every control tick, and nearly always one controller drives the arm and one the
hand; that case is passed straight through rather than merged DOF by DOF.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from primitives.base import ControlData, HandCommand
from primitives.robot import HandMode


@dataclass
class RobotCommand:
    twist: np.ndarray | None  # (6,) TCP twist, world frame; None: no controller gives one
    joint_velocity: np.ndarray | None  # (arm_dof,) added after the twist is resolved; None: none given
    hand_values: np.ndarray | None  # None: no controller drives the hand
    hand_modes: tuple[HandMode, ...]


def _mean(pairs: list[tuple[np.ndarray, float]]) -> np.ndarray | None:
    if len(pairs) == 1:
        vector, weight = pairs[0]
        return vector if weight > 0 else None
    total = sum(w for _, w in pairs)
    if not pairs or total <= 0:
        return None
    return sum(v * w for v, w in pairs) / total


def _hand(hands: list[HandCommand], hand_dof: int) -> tuple[np.ndarray | None, tuple[HandMode, ...]]:
    if len(hands) == 1 and not np.count_nonzero(np.isnan(hands[0].values)):  # one controller drives every DOF
        return np.array(hands[0].values, float), tuple(hands[0].modes)
    values = np.full(hand_dof, np.nan)
    modes = [HandMode.VELOCITY] * hand_dof
    best = [-np.inf] * hand_dof
    for hand in hands:
        for dof, value in enumerate(hand.values.tolist()):
            if not math.isnan(value) and hand.weight >= best[dof]:
                best[dof], values[dof], modes[dof] = hand.weight, value, hand.modes[dof]
    undriven = np.isnan(values)
    if undriven.all():
        return None, tuple(modes)
    values[undriven] = 0.0  # an undriven DOF is told to stand still
    return values, tuple(modes)


def arbitrate(outputs: list[ControlData], hand_dof: int) -> RobotCommand:
    twists = [(np.asarray(o.arm.twist, float), o.arm.weight) for o in outputs if o.arm and o.arm.twist is not None]
    joints = [(np.asarray(o.arm.joint_velocity, float), o.arm.weight)
              for o in outputs if o.arm and o.arm.joint_velocity is not None]
    values, modes = _hand([o.hand for o in outputs if o.hand is not None], hand_dof)
    return RobotCommand(twist=_mean(twists), joint_velocity=_mean(joints), hand_values=values, hand_modes=modes)
