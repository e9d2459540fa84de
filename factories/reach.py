"""Can the arm put its TCP there, with the hand turned as the task turns it? Asked of the
robot's own description.

A hand pointing down is checked by inverse kinematics on the same description the
simulator builds; answers are remembered per point. A turned hand is rehearsed: the arm
is moved from home, kinematically, by the resolved-rate law the run moves it by
(`atd.model.resolved_rate`, sparing joints near their limits), so a target the run would
stall short of, a joint at its limit or the arm at a singularity, is refused with what
stopped it. A point beyond the arm's stretched length is refused at once.
"""

from __future__ import annotations

import numpy as np

from atd.model.resolved_rate import TWIST_DAMPING, joints_at_limits, limited_joint_velocities, rotation_error
from atd.model.task import Vec3
from factories.description import RobotDescription

TOLERANCE = 0.002  # m: closer than this counts as reaching the point
TURNED_WITHIN = np.radians(2.0)  # rad: a turned hand this near its orientation has made it (the arms' tolerance)
STEP = 0.05  # s of the rehearsal's motion per step
SPEED = 0.15  # m/s, rad/s: the rehearsal moves no faster (the arm controllers' cruise)
GAIN = 4.0  # 1/s: the arm controllers' proportional gain
PATIENCE = 1.0  # s of rehearsal without getting PROGRESS closer: stalled
PROGRESS = 0.001  # m, or rad, closer
LONGEST = 15.0  # s of rehearsal at most
SINGULAR = 0.005  # m: the Jacobian's smallest singular value below which the arm is at a singularity


class Reach:
    def __init__(self, robot: RobotDescription) -> None:
        self.robot = robot
        self.home = np.asarray(robot.home, float)
        home_tcp = robot.tcp_pose(self.home)
        # Top-down (hand z = world -z), keeping the yaw the hand has at home.
        x = np.array([home_tcp[0, 0], home_tcp[1, 0], 0.0])
        x = x / np.linalg.norm(x) if np.linalg.norm(x) > 1e-6 else np.array([1.0, 0.0, 0.0])
        z = np.array([0.0, 0.0, -1.0])
        self.rotation = np.column_stack([x, np.cross(z, x), z])
        poses = robot.link_poses(dict(zip(robot.arm_joints, self.home)))
        first = robot.joint_link[robot.arm_joints[0]]
        self.shoulder = poses[first][:3, 3]
        chain = [poses[robot.joint_link[j]][:3, 3] for j in robot.arm_joints] + [home_tcp[:3, 3]]
        self.stretched = float(sum(np.linalg.norm(b - a) for a, b in zip(chain, chain[1:])))
        self.lower = np.array([robot.joints[n].lower for n in robot.arm_joints])
        self.upper = np.array([robot.joints[n].upper for n in robot.arm_joints])
        self.speeds = np.array([robot.joints[n].velocity for n in robot.arm_joints])
        # per point and rotation: why the arm does not get there (None: it does), and the joints it ends at
        self._known: dict[tuple[float, ...], tuple[str | None, np.ndarray]] = {}

    def reachable(self, point: Vec3) -> bool:
        """The TCP at `point` with the hand pointing down (its home yaw)."""
        return self.why_not(point, self.rotation) is None

    def why_not(self, point: Vec3, rotation: np.ndarray) -> str | None:
        """None when the arm puts the TCP at `point` with the hand's `rotation` (world), else
        what stops it: 'beyond the arm's reach', the joint at its limit, or a singularity."""
        return self._solved(point, rotation)[0]

    def margin(self, point: Vec3, rotation: np.ndarray) -> float:
        """How near its limit (rad, or m for a sliding joint) the arm's closest joint stands
        where it gets to `point` with the hand's `rotation`: room left for an approach that
        arrives turned off its plan."""
        q = self._solved(point, rotation)[1]
        return float(np.min(np.minimum(q - self.lower, self.upper - q)))

    def _solved(self, point: Vec3, rotation: np.ndarray) -> tuple[str | None, np.ndarray]:
        key = tuple(round(float(v), 4) for v in (*point, *np.asarray(rotation).ravel()))
        if key not in self._known:
            self._known[key] = self._solve(np.asarray(point, float), np.asarray(rotation, float))
        return self._known[key]

    def _solve(self, point: np.ndarray, rotation: np.ndarray) -> tuple[str | None, np.ndarray]:
        if np.linalg.norm(point - self.shoulder) > self.stretched:
            return (f"it lies {np.linalg.norm(point - self.shoulder):.2f} m from the shoulder, beyond the arm's reach",
                    self.home)
        target = np.eye(4)
        target[:3, :3] = rotation
        target[:3, 3] = point
        if np.allclose(rotation, self.rotation):
            q, error = self.robot.inverse_kinematics(target, self.home)
            return None if error < TOLERANCE else "the arm cannot put the TCP there with the hand pointing down", q
        return self._rehearse(target)

    def _rehearse(self, target: np.ndarray) -> tuple[str | None, np.ndarray]:
        """Move from home towards `target` as the run would; None once there, else why not;
        with the joints where it ended."""
        q = self.home.copy()
        best, best_at, t = np.inf, 0.0, 0.0
        while t < LONGEST:
            pose = self.robot.tcp_pose(q)
            offset = target[:3, 3] - pose[:3, 3]
            turn = rotation_error(target[:3, :3], pose[:3, :3])
            distance, angle = float(np.linalg.norm(offset)), float(np.linalg.norm(turn))
            if distance < TOLERANCE and angle < TURNED_WITHIN:
                return None, q
            if distance + angle < best - PROGRESS:
                best, best_at = distance + angle, t
            elif t - best_at > PATIENCE:
                return self._stopped(q, distance, angle), q
            twist = np.concatenate([_clamp(GAIN * offset, SPEED), _clamp(GAIN * turn, SPEED * 4)])
            jacobian = self.robot.tcp_jacobian(q)
            dq = limited_joint_velocities(jacobian, twist, TWIST_DAMPING, q, self.lower, self.upper)
            q = np.clip(q + np.clip(dq, -self.speeds, self.speeds) * STEP, self.lower, self.upper)
            t += STEP
        return self._stopped(q, distance, angle), q

    def _stopped(self, q: np.ndarray, distance: float, angle: float) -> str:
        """What stops an arm stalled at `q`, `distance` and `angle` short of its target."""
        short = f"{distance * 100:.1f} cm and {np.degrees(angle):.0f} degrees short"
        at_limit = joints_at_limits(q, self.robot.arm_joints, self.lower, self.upper)
        if at_limit:
            return f"the arm stops {short}, {' and '.join(at_limit)}"
        smallest = float(np.linalg.svd(self.robot.tcp_jacobian(q), compute_uv=False)[-1])
        if smallest < SINGULAR:
            return f"the arm stops {short}, at a singularity (no joint moves the hand the way it must go)"
        return f"the arm stops {short}, making no progress"


def _clamp(v: np.ndarray, limit: float) -> np.ndarray:
    n = float(np.linalg.norm(v))
    return v * (limit / n) if n > limit else v
