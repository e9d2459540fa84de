"""Can the arm put its TCP there, hand pointing down? Asked of the robot's own description.

The answer comes from inverse kinematics on the same description the simulator builds,
so translation refuses exactly what the simulated robot could not do. A point beyond
the arm's stretched length is refused at once; answers are remembered per point.
"""

from __future__ import annotations

import numpy as np

from atd.model.task import Vec3
from factories.description import RobotDescription

TOLERANCE = 0.002  # m: closer than this counts as reaching the point


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
        self._known: dict[tuple[float, ...], bool] = {}

    def reachable(self, point: Vec3) -> bool:
        key = tuple(round(float(v), 4) for v in point)
        if key not in self._known:
            self._known[key] = self._solve(np.asarray(point, float))
        return self._known[key]

    def _solve(self, point: np.ndarray) -> bool:
        if np.linalg.norm(point - self.shoulder) > self.stretched:
            return False
        target = np.eye(4)
        target[:3, :3] = self.rotation
        target[:3, 3] = point
        _, error = self.robot.inverse_kinematics(target, self.home)
        return error < TOLERANCE
