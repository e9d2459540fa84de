"""The container as the robot believes it (the task's knowledge, never the simulator's), and
the top-down approach above a point in it that every generator of thesis 3.4.3 ends with."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

import numpy as np

from atd.model.controllers import ParamValue
from atd.model.task import ContainerInfo
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
    def known(cls, info: ContainerInfo) -> ContainerBelief:
        """From a container the task's <environment> names."""
        return cls.of(info.pose.as_array(), np.asarray(info.size, float), info.wall)

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


def room_for_hand(container: ContainerBelief, rotation: np.ndarray, extent: tuple[float, float]) -> np.ndarray:
    """How far (x y, its own frame) from its middle a top-down TCP turned by `rotation` (world)
    may go before the hand, reaching `extent` (along its own x, along its y) sideways, meets a
    wall: 0 along an axis where the hand does not fit."""
    axes = container.pose[:3, :3].T @ rotation  # the hand's axes in the container's frame
    reach = np.abs(axes[:2, 0]) * extent[0] + np.abs(axes[:2, 1]) * extent[1]
    return np.maximum(container.inner[:2] / 2 - reach, 0.0)


def container_under(containers: list[ContainerBelief], position: np.ndarray) -> ContainerBelief | None:
    """The container whose inside `position` (world) is over, if any."""
    for container in containers:
        local = container.to_local(np.asarray(position, float)[None])[0]
        if np.all(np.abs(local[:2]) <= container.inner[:2] / 2):
            return container
    return None


def clear_of_walls(containers: list[ContainerBelief], tcp: np.ndarray, extent: tuple[float, float],
                   start: np.ndarray | None = None, offset: tuple[float, float] = (0.0, 0.0)) -> np.ndarray:
    """The TCP pose `tcp` (4x4, world) moved sideways, as little as it takes, so that a hand
    reaching `extent` (along its x, along its y) either way from the middle of its footprint,
    `offset` from the TCP (along its x and y: a hand whose thumb reaches further one way than
    its fingers the other), stays inside the walls of the container it is over, or of the one
    a move to it starts over (`start`, world: a move from inside a box to beyond its wall goes
    into the wall); unchanged over none (a grasp on the table). Moves along the walls are
    free, so a grasp's corrections slide along a wall instead of pressing into it."""
    container = container_under(containers, tcp[:3, 3])
    if container is None and start is not None:
        container = container_under(containers, start)
    if container is None:
        return tcp
    shift = tcp[:3, :3] @ np.array([offset[0], offset[1], 0.0])
    local = container.to_local(tcp[None, :3, 3] + shift)[0]
    room = room_for_hand(container, tcp[:3, :3], extent)
    local[:2] = np.clip(local[:2], -room, room)
    moved = tcp.copy()
    moved[:3, 3] = container.to_world(local[None])[0] - shift
    return moved


def approach_pose(container: ContainerBelief, point: np.ndarray, reach: float, height: float,
                  yaw: float = 0.0) -> np.ndarray:
    """The top-down TCP pose over `point` (world) from which a grasp descends: the hand's
    lowest point (`reach` below the TCP) `height` above the higher of the point and the
    container's rim, so the hand comes over the walls, whatever it found; the hand's x `yaw`
    (rad) from the container's x about the vertical."""
    c, s = np.cos(yaw), np.sin(yaw)
    turned = container.pose[:3, :3] @ np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    pose = np.eye(4)
    pose[:3, :3] = top_down(turned)
    pose[:3, 3] = (point[0], point[1], max(float(point[2]), container.rim) + height + reach)
    return pose
