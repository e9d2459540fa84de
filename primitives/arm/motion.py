"""Cartesian velocity building blocks shared by every arm controller.

Thesis 3.3.2: a Cartesian velocity law v = n (x_target - x_current), kept inside velocity
limits, resolved to joint velocities by the robot (damped least squares). Here too: the
proportional law with its gains, orientation errors, the twist shaper that enforces
velocity and acceleration limits, and the detour around known obstacles.
"""

from __future__ import annotations

import math
from typing import Callable, Sequence

import numpy as np

from atd.model.resolved_rate import TURN_MARGIN, joints_at_limits, rotation_error

GAIN = 4.0  # 1/s: linear P gain; 3 mm from the target the TCP still moves at 12 mm/s
ROTATION_GAIN = 3.0  # 1/s
MAX_ANGULAR_SPEED = 1.0  # rad/s
ORIENTATION_TOLERANCE = math.radians(2.0)

# Our smoothing, always on: a velocity step of 0.15 m/s in one 5 ms tick would shake the
# hand with tens of newtons of inertial force, which the wrist sensor cannot tell from a
# contact. 1 m/s^2 costs 0.15 s of ramp and keeps inertial forces near 1.5 N.
LINEAR_ACCELERATION = 1.0  # m/s^2
ANGULAR_ACCELERATION = 4.0  # rad/s^2

# rad a move given a `yaw` may leave the hand's x from where the first such move found it:
# a half-turn band and a quarter either side, so no turn need be more than a half turn
WIND_LIMIT = math.radians(135.0)
STALL_TIME = 2.0  # s without getting STALL_PROGRESS closer: the arm cannot get there
STALL_PROGRESS = 0.001  # m
STALL_TURN = math.radians(0.5)  # a quarter of ORIENTATION_TOLERANCE: a hand still turning is getting there

WORLD_DOWN = np.array([0.0, 0.0, -1.0])
SUPPORT_BAND = 0.01  # m: fingertips this close to the support's top (the world's z = 0) stand on it


def top_down(rotation: np.ndarray) -> np.ndarray:
    """The top-down hand orientation nearest `rotation`: hand z = world -z, the hand's x
    axis kept as it points now (projected on the table plane), so the grasp keeps its yaw."""
    x = rotation[:, 0] - rotation[2, 0] * np.array([0.0, 0.0, 1.0])
    if np.linalg.norm(x) < 1e-6:  # hand x points straight up or down: take hand y's yaw
        x = np.cross(rotation[:, 1], WORLD_DOWN)
    x /= np.linalg.norm(x)
    z = WORLD_DOWN
    return np.column_stack([x, np.cross(z, x), z])


def turn_to_yaw(level: np.ndarray, yaw: float, reference: float, either_way: bool = True,
                room: Callable[[float], float] | None = None) -> np.ndarray:
    """The turn about the world vertical (3x3) that brings the top-down hand `level`'s x to
    `yaw` (rad, from the world x) or the opposite way: the smaller of the two (parallel jaws
    grip alike either way, so the wrist turns at most a quarter turn), unless it takes the
    hand's x more than WIND_LIMIT from `reference` (rad): then the other, so turn after turn
    cannot wind the wrist up (a vision trial that emptied a box on the Melfa, always turning
    the shorter way, took j6 to its limit at -360 degrees). Given `room` (a turn, rad -> how far
    the joint that rolls the hand ends from its nearer limit), the other way too where the
    first would leave that joint less than TURN_MARGIN and the other leaves it more, as a grasp
    turn the factory plans keeps it (`factories.base`, `coming_down`). Not `either_way`: to `yaw`
    itself (a factory that chose the longer turn to keep a wrist off its stop, an approach whose half
    turn matters), by the shorter way round; given `room`, the opposite way after all where `yaw`
    would leave that joint less than TURN_MARGIN and the opposite more (the SDH2's wrist, turned
    to the yaw that put its thumb towards the middle of a box, stopped at its limit and the arm
    with it: a thumb towards a wall is the lesser harm)."""
    heading = heading_of(level)
    if not either_way:
        turn = (yaw - heading + math.pi) % (2 * math.pi) - math.pi
        return about_vertical(_roomier(turn, room))
    turn = (yaw - heading + math.pi / 2) % math.pi - math.pi / 2
    if abs((heading + turn - reference + math.pi) % (2 * math.pi) - math.pi) > WIND_LIMIT:
        turn -= math.copysign(math.pi, turn)
    return about_vertical(_roomier(turn, room))


def _roomier(turn: float, room: Callable[[float], float] | None) -> float:
    """`turn`, or half a turn the other way where `turn` would leave the joint that rolls the
    hand less than TURN_MARGIN from its limit (`room`) and that leaves it more."""
    if room is not None and room(turn) < TURN_MARGIN:
        other = turn - math.copysign(math.pi, turn)
        if room(other) > room(turn):
            return other
    return turn


def about_vertical(turn: float) -> np.ndarray:
    """The rotation by `turn` (rad) about the world vertical."""
    c, s = math.cos(turn), math.sin(turn)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def roll_room(arm_q: np.ndarray, lower: np.ndarray, upper: np.ndarray,
              wrist_roll: float) -> Callable[[float], float] | None:
    """How far a turn of the hand about the vertical (rad) leaves the last arm joint (its
    position and limits the last of `arm_q`, `lower`, `upper`) from its nearer limit, that
    joint turning `wrist_roll` times the turn (the factory's); None where it does not roll
    the hand (`wrist_roll` 0)."""
    if not wrist_roll:
        return None
    now, low, high = float(arm_q[-1]), float(lower[-1]), float(upper[-1])

    def room(turn: float) -> float:
        q = now + wrist_roll * turn
        return min(q - low, high - q)
    return room


def heading_of(rotation: np.ndarray) -> float:
    """The yaw (rad, from the world x) of a hand's x about the world vertical."""
    return math.atan2(float(rotation[1, 0]), float(rotation[0, 0]))


def norm(v: np.ndarray) -> float:
    """Euclidean norm of a short vector (a fraction of np.linalg.norm's cost, every tick)."""
    return math.sqrt(float(v.dot(v)))


def clamp_norm(v: np.ndarray, limit: float) -> np.ndarray:
    n = norm(v)
    return v * (limit / n) if n > limit > 0.0 else v


def orientation_twist(goal: np.ndarray, current: np.ndarray) -> tuple[np.ndarray, float]:
    """Angular velocity towards `goal`, and the angle still to turn."""
    err = rotation_error(goal, current)
    angle = norm(err)
    return clamp_norm(ROTATION_GAIN * err, MAX_ANGULAR_SPEED), angle


class TwistShaper:
    """Keeps a commanded twist within the velocity and acceleration limits (thesis 3.3.2
    VELOCITY_LIMITS, ACCELERATION_LIMITS: per axis, zero = no limit), and always within
    our gentle acceleration ramp."""

    def __init__(self, velocity_limits: Sequence[float] = (0.0,) * 6,
                 acceleration_limits: Sequence[float] = (0.0,) * 6) -> None:
        vel = np.asarray(velocity_limits, float)
        acc = np.asarray(acceleration_limits, float)
        self._vel = np.where(vel > 0.0, vel, np.inf) if (vel > 0.0).any() else None
        self._acc = np.where(acc > 0.0, acc, np.inf) if (acc > 0.0).any() else None
        self.last = np.zeros(6)

    def start(self, twist: np.ndarray | None) -> None:
        """Take over an arm moving at `twist` (None: at rest)."""
        self.last = np.zeros(6) if twist is None else np.array(twist, float)

    def stop(self) -> np.ndarray:
        """An immediate stop (a contact does not wait for a ramp)."""
        self.last = np.zeros(6)
        return self.last

    def __call__(self, twist: np.ndarray, dt: float) -> np.ndarray:
        wanted = twist if self._vel is None else np.minimum(np.maximum(twist, -self._vel), self._vel)
        change = wanted - self.last
        if self._acc is not None:
            step = self._acc * dt
            change = np.minimum(np.maximum(change, -step), step)
        change[:3] = clamp_norm(change[:3], LINEAR_ACCELERATION * dt)
        change[3:] = clamp_norm(change[3:], ANGULAR_ACCELERATION * dt)
        self.last = self.last + change
        return self.last


class ObstacleDetour:
    """Routes around known box obstacles (thesis 3.3.2 OBSTACLES): up, across, down.

    Each box is grown by `clearance` (the hand's reach around the TCP). A straight leg
    that would cross a grown box is replaced by a climb to just above the highest box in
    the way, a level leg, and a descent onto the goal. Obstacles stand on the table, so
    over the top is always a way round, and unlike a repulsive field this cannot stall
    in a local minimum in front of a box. A box that holds the leg's start or goal (a
    goal right beside an obstacle) cannot be kept clear of and is not routed around.
    """

    def __init__(self, centres: Sequence[Sequence[float]], sizes: Sequence[Sequence[float]],
                 clearance: float = 0.05) -> None:
        centres = np.asarray(centres, float).reshape(-1, 3)
        sizes = np.asarray(sizes, float).reshape(-1, 3) if len(sizes) else np.zeros_like(centres)
        self._low = centres - sizes / 2 - clearance
        self._high = centres + sizes / 2 + clearance

    def route(self, start: np.ndarray, goal: np.ndarray) -> list[np.ndarray]:
        """The points to visit after `start`, ending with `goal`."""
        blocking = self._crossed(start, goal)
        if not blocking:
            return [goal]
        height = max(start[2], goal[2])
        while blocking:  # raise the level leg until it crosses nothing
            height = max(height, max(self._high[i][2] for i in blocking))
            up = np.array([start[0], start[1], height])
            over = np.array([goal[0], goal[1], height])
            blocking = [i for i in self._crossed(up, over) if self._high[i][2] > height]
        return [up, over, goal]

    def _crossed(self, a: np.ndarray, b: np.ndarray) -> list[int]:
        """Boxes the segment a-b passes through, other than those holding a or b (slab test)."""
        crossed = []
        d = b - a
        for i, (low, high) in enumerate(zip(self._low, self._high)):
            if _inside(a, low, high) or _inside(b, low, high):
                continue
            enter, leave = 0.0, 1.0
            for k in range(3):
                if abs(d[k]) < 1e-12:
                    if not low[k] <= a[k] <= high[k]:
                        break
                    continue
                t0, t1 = sorted(((low[k] - a[k]) / d[k], (high[k] - a[k]) / d[k]))
                enter, leave = max(enter, t0), min(leave, t1)
                if enter > leave:
                    break
            else:
                crossed.append(i)
        return crossed


class Stall:
    """Whether a motion has stopped getting nearer where it goes: `patience` (STALL_TIME unless
    told) without coming STALL_PROGRESS nearer than its best, nor turning STALL_TURN nearer
    where it also turns (a joint at its limit, a singularity, something in the way). Every arm
    controller that goes somewhere ends on it rather than wait for ever."""

    def __init__(self, patience: float = STALL_TIME) -> None:
        self.patience = patience  # s without progress that count as stalled
        self.reset(0.0)

    def reset(self, now: float, distance: float = math.inf) -> None:
        """A new goal, `distance` (m) away as far as is known at `now` (s)."""
        self.best = distance
        self.best_angle = math.inf
        self.best_time = now

    def stalled(self, distance: float, now: float, angle: float | None = None) -> bool:
        """`distance` (m) and `angle` (rad, for a motion that turns the hand too) still to go at
        `now` (s): True once neither has shrunk for `patience` (a hand that has arrived but still
        turns is getting there; docs/open-bottle.md, *PyBullet*)."""
        closer = distance < self.best - STALL_PROGRESS
        turned = angle is not None and angle < self.best_angle - STALL_TURN
        if closer:
            self.best = distance
        if turned:
            self.best_angle = angle
        if closer or turned:
            self.best_time = now
            return False
        return now - self.best_time > self.patience


def _inside(p: np.ndarray, low: np.ndarray, high: np.ndarray) -> bool:
    return bool(np.all(p >= low) and np.all(p <= high))


def unit(vector) -> np.ndarray:
    """The vector scaled to length 1 (directions and normals come as any length)."""
    v = np.asarray(vector, float)
    return v / np.linalg.norm(v)


def what_stops(arm_q: np.ndarray, joints: Sequence[str], lower: np.ndarray, upper: np.ndarray) -> str:
    """Why an arm that makes no progress stops: the joints at their limits, named, or else
    a singularity or something in the way (the arm cannot tell them apart)."""
    named = joints_at_limits(arm_q, joints, lower, upper)
    return " and ".join(named) if named else "no joint at its limit: a singularity, or something in the way"
