"""The container as the robot believes it (the task's knowledge, never the simulator's), and
the top-down approach above a point in it that every generator of thesis 3.4.3 ends with."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

import numpy as np

from atd.model.controllers import ParamValue
from primitives.arm.motion import top_down


@dataclass(frozen=True)
class ContainerBelief:
    """An open box: `pose` is its frame at the centre of its floor's top face (the inside's
    bottom), `inner` the room inside, x y z along its own axes."""

    pose: np.ndarray  # (4, 4), world
    inner: np.ndarray  # (3,), m

    @classmethod
    def of(cls, pose: np.ndarray, size: np.ndarray, wall: float) -> ContainerBelief:
        """From the frame at the centre of its floor's underside, its outer size and its wall
        thickness: how a world file and an ATD give a container (docs/worlds.md)."""
        size = np.asarray(size, float)
        floor = np.array(pose, float)
        floor[:3, 3] = floor[:3, 3] + wall * floor[:3, 2]
        return cls(floor, size - np.array([2 * wall, 2 * wall, wall]))

    @classmethod
    def from_params(cls, params: Mapping[str, ParamValue]) -> ContainerBelief:
        """From a controller's `container_pose` (16 numbers, row-major), `container_size` and
        `container_wall` parameters; ValueError for a pose that is not a rigid transform."""
        pose = np.asarray(params["container_pose"], float).reshape(4, 4)
        rotation = pose[:3, :3]
        if not np.allclose(rotation.T @ rotation, np.eye(3), atol=1e-6) or not np.allclose(pose[3], (0, 0, 0, 1)):
            raise ValueError("container_pose is not a rigid transform (a rotation and a translation, row-major)")
        return cls.of(pose, np.asarray(params["container_size"], float), float(params["container_wall"]))

    @property
    def floor(self) -> float:
        """World z of the inside's floor (the container standing upright)."""
        return float(self.pose[2, 3])

    @property
    def rim(self) -> float:
        """World z of the top of its walls."""
        return self.floor + float(self.inner[2])

    def to_local(self, points: np.ndarray) -> np.ndarray:
        """(n, 3) world points in the container's frame."""
        return (np.asarray(points, float) - self.pose[:3, 3]) @ self.pose[:3, :3]

    def to_world(self, points: np.ndarray) -> np.ndarray:
        """(n, 3) points of the container's frame in the world."""
        return np.asarray(points, float) @ self.pose[:3, :3].T + self.pose[:3, 3]

    def footprint(self, margin: float) -> tuple[np.ndarray, np.ndarray]:
        """(low, high) x y corners, in its own frame, of the floor less `margin` from every wall
        (a point where nothing fits: both at the middle)."""
        half = np.maximum(self.inner[:2] / 2 - margin, 0.0)
        return -half, half


def approach_pose(container: ContainerBelief, point: np.ndarray, reach: float, height: float) -> np.ndarray:
    """The top-down TCP pose over `point` (world) from which a grasp descends: the hand's
    lowest point (`reach` below the TCP) `height` above the higher of the point and the
    container's rim, so the hand comes over the walls, whatever it found; the hand's x along
    the container's x."""
    pose = np.eye(4)
    pose[:3, :3] = top_down(container.pose[:3, :3])
    pose[:3, 3] = (point[0], point[1], max(float(point[2]), container.rim) + height + reach)
    return pose
