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


def with_home(robot: RobotDescription, start: tuple[float, ...], tcp: Vec3 = HOME_TCP) -> RobotDescription:
    """`robot` with its `home` set to the arm joints that put the TCP at `tcp`, hand pointing
    down, searched for by inverse kinematics from the joint positions `start`."""
    target = np.eye(4)
    target[:3, :3] = HAND_DOWN
    target[:3, 3] = tcp
    q, error = robot.inverse_kinematics(target, np.asarray(start, float), iterations=1000, tolerance=1e-7)
    if error > TOLERANCE:
        raise ValueError(f"robot '{robot.name}': no home found with the TCP at ({', '.join(f'{v:g}' for v in tcp)}) "
                         f"and the hand pointing down ({error * 1000:.1f} mm short); move `base` closer to the "
                         "work area, or give a `start` nearer such a posture")
    return replace(robot, home=tuple(round(float(v), 4) for v in q))
