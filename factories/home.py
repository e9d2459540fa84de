"""A robot's home posture, found from its description rather than typed in.

Every built-in robot starts with its TCP 15 cm above the middle of the work area, hand
pointing down, hand y along world y; a new robot found the same way starts where the
examples expect, and stays right when its links are edited.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from factories.description import RobotDescription, Vec3

HOME_TCP = (0.125, 0.0, 0.15)  # m, ATD world frame: above the middle of the work area
HAND_DOWN = np.diag([-1.0, 1.0, -1.0])  # hand z down, hand x towards the robot
TOLERANCE = 1e-4  # m
STARTS = 8  # postures tried when no start is given: the middle of every range, then random ones


def _room(robot: RobotDescription, q: np.ndarray) -> float:
    """How far the nearest joint is from a limit, as a share of its range: a home near a
    limit leaves the arm no room to move."""
    lower = np.array([robot.joints[n].lower for n in robot.arm_joints])
    upper = np.array([robot.joints[n].upper for n in robot.arm_joints])
    return float(np.min(np.minimum(q - lower, upper - q) / (upper - lower)))


def with_home(robot: RobotDescription, start: tuple[float, ...] | None = None,
              tcp: Vec3 = HOME_TCP) -> RobotDescription:
    """`robot` with its `home` set to the arm joints that put the TCP at `tcp`, hand pointing
    down: found by inverse kinematics from `start`, or, without one, from the middle of
    every joint's range and from random postures, keeping the one farthest from the limits."""
    target = np.eye(4)
    target[:3, :3] = HAND_DOWN
    target[:3, 3] = tcp
    if start is not None:
        starts = [np.asarray(start, float)]
    else:
        lower = np.array([robot.joints[n].lower for n in robot.arm_joints])
        upper = np.array([robot.joints[n].upper for n in robot.arm_joints])
        draws = np.random.default_rng(0).uniform(lower, upper, (STARTS - 1, len(lower)))
        starts = [(lower + upper) / 2, *draws]
    found = []
    for begin in starts:
        q, error = robot.inverse_kinematics(target, begin, iterations=400, tolerance=1e-7)
        if error <= TOLERANCE:
            found.append(q)
    if not found:
        raise ValueError(f"robot '{robot.name}': no home found with the TCP at ({', '.join(f'{v:g}' for v in tcp)}) "
                         f"and the hand pointing down; move `base` closer to the work area, or give a `start` "
                         "nearer such a posture")
    best = max(found, key=lambda q: _room(robot, q))
    return replace(robot, home=tuple(round(float(v), 4) for v in best))
