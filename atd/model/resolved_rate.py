"""Resolved-rate control: a TCP twist as joint velocities, the same way for the arm controllers
(`primitives.robot.Robot.twist_velocities`) and the translation's reach check
(`factories.reach`), so a check rehearses the motion the run will make."""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np
from numpy.linalg import _umath_linalg

_IDENTITY6 = np.eye(6)  # built once: adding it costs far less than indexing the diagonal every tick
TWIST_DAMPING = 0.02  # m: the damping of the Cartesian velocity solver, in the units of the Jacobian
LIMIT_BAND = 0.05  # of a joint's range: a joint this near a limit does less of a motion towards it
# rad each joint keeps from its limits where a turn of the hand is chosen (a grasp's planned turn, a
# move's turn to a perceived yaw): the approach error turns the hand up to 15°
TURN_MARGIN = math.radians(15.0)


def dls_joint_velocities(jacobian: np.ndarray, twist: np.ndarray, damping: float) -> np.ndarray:
    """Damped least-squares inverse kinematics (thesis 6.3.2): dq = J^T (J J^T + l^2 I)^-1 v.

    The damping keeps joint speeds bounded near singularities at the price of a small
    tracking error there. (`.dot` rather than `@`: on 6 x 7 arrays, every tick, it costs half as much.)
    """
    return jacobian.T.dot(_solve(jacobian.dot(jacobian.T) + (damping * damping) * _IDENTITY6, twist))


def _solve(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """`np.linalg.solve(a, b)` for a 6 x 6 `a` and a vector `b`, by the same LAPACK call without
    the wrapper's checks and error state, which cost three times the solve itself every tick.
    A result that is not finite (a singular `a`: a Jacobian with NaNs in it) is solved again
    by numpy's own, which raises as it always did."""
    x = _umath_linalg.solve1(a, b, signature="dd->d")
    return x if math.isfinite(float(x.sum())) else np.linalg.solve(a, b)


def limited_joint_velocities(jacobian: np.ndarray, twist: np.ndarray, damping: float, q: np.ndarray,
                             lower: np.ndarray, upper: np.ndarray) -> np.ndarray:
    """Damped least squares that spares joints near their limits (weighted least norm, Chan
    and Dubey 1995): a joint within LIMIT_BAND of a limit and moving towards it takes a
    share of the motion that falls to nothing at the limit, and the other joints make up
    the rest where they can. At a six-axis arm's wrist singularity the forearm roll (j4)
    and the flange roll (j6) turn the hand alike: plain DLS shared a turn between them and
    drove the Melfa's j4 onto its limit, a hardware failure (PyBullet, 11 of the robust
    grasp's 100 trials with the seeds' approach error in the preset)."""
    dq = dls_joint_velocities(jacobian, twist, damping)
    # Each joint's room before the limit it moves towards, in LIMIT_BAND of its range: in plain
    # floats, as on 6-7 joints every tick numpy's calls cost several times their arithmetic.
    room = [(high - value if speed > 0.0 else value - low) / (LIMIT_BAND * (high - low))
            for speed, value, low, high in zip(dq.tolist(), q.tolist(), lower.tolist(), upper.tolist())]
    if all(r >= 1.0 for r in room):  # every joint clear of its limits: nearly every tick
        return dq
    weight = np.clip(np.array(room), 0.0, 1.0)
    return weight * dls_joint_velocities(jacobian * weight, twist, damping)


def rotation_error(goal: np.ndarray, current: np.ndarray) -> np.ndarray:
    """World-frame rotation vector (axis * angle) that turns `current` into `goal`."""
    r = goal.dot(current.T).tolist()  # plain floats: nine element reads cost less than on an array
    cos = max(-1.0, min(1.0, (r[0][0] + r[1][1] + r[2][2] - 1.0) / 2.0))
    angle = math.acos(cos)
    if angle < 1e-9:
        return np.zeros(3)
    if math.pi - angle < 1e-6:  # half a turn: the axis is the eigenvector of r for eigenvalue 1
        return np.array([math.sqrt(max(0.0, (r[k][k] + 1.0) / 2.0)) * angle for k in range(3)])
    scale = angle / (2.0 * math.sin(angle))
    return np.array([(r[2][1] - r[1][2]) * scale, (r[0][2] - r[2][0]) * scale, (r[1][0] - r[0][1]) * scale])


def joints_at_limits(q: np.ndarray, names: Sequence[str], lower: np.ndarray, upper: np.ndarray) -> list[str]:
    """The joints within LIMIT_BAND of a limit, where `limited_joint_velocities` slows them,
    each as "joint 'NAME' at its lower/upper limit (VALUE)": what stops an arm that stalls."""
    found = []
    for name, value, low, high in zip(names, q, lower, upper):
        if min(value - low, high - value) < LIMIT_BAND * (high - low):
            side, limit = ("lower", low) if value - low < high - value else ("upper", high)
            found.append(f"joint '{name}' at its {side} limit ({limit:.2f})")
    return found
