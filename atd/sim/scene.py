"""The world a robot works in, from an ATD's `<object>` and `<environment>`.

Everything is in the ATD world frame: the table top is the plane z = 0 and x points away
from the robot. The object is free to move; obstacles are fixed.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import numpy as np

from atd.model import ObjectClass, Task
from atd.model.files import real_path
from atd.model.meshcheck import MeshError, check_mesh

DEFAULT_WEIGHT = 0.2  # kg, when the ATD gives none
DEFAULT_FRICTION = 1.0  # object against pads and table
DEFAULT_OBSTACLE_SIZE = (0.05, 0.05, 0.05)

# Table top z = 0: from just in front of the robots' bases to well past the work area.
TABLE_CENTRE = (0.2, 0.0, -0.025)
TABLE_HALF = (0.32, 0.6, 0.025)

# Where pictures of the scene look from: a view of the work area from the front left.
CAMERA_TARGET = (0.1, 0.0, 0.1)
CAMERA_DISTANCE = 1.4
CAMERA_AZIMUTH = 150.0  # degrees about z, from +x
CAMERA_ELEVATION = -25.0  # degrees


class SceneError(ValueError):
    """The ATD describes something the simulator cannot build; the message says what to fix."""


@dataclass(frozen=True)
class Body:
    """A simulated object. `size` follows `atd.model.vocabulary.SIZE_LAYOUT` for the
    class (box x y z full lengths, cylinder radius height, sphere radius); for a mesh it is
    the bounding box used for the inertia.

    A mesh file is scaled by `mesh_scale` in its own axes, then placed by `mesh_frame` in
    the body's frame. The engines collide with the convex hull of the mesh or, for a
    concave mesh, with each of its convex `mesh_parts` (files in the mesh's own frame)."""

    name: str
    kind: Literal["box", "cylinder", "sphere", "mesh"]
    size: tuple[float, ...]
    pose: np.ndarray  # 4x4, the body's geometric centre
    mass: float
    friction: float
    mesh: Path | None = None
    mesh_scale: tuple[float, float, float] = (1.0, 1.0, 1.0)
    mesh_frame: np.ndarray | None = None  # 4x4; None: the body's own frame
    mesh_parts: tuple[Path, ...] = ()

    @property
    def collision_meshes(self) -> tuple[Path, ...]:
        """The files the engines build the object's collision geometry from."""
        return self.mesh_parts or ((self.mesh,) if self.mesh is not None else ())

    @property
    def rolls(self) -> bool:
        """It rests on the table at one point, so only rolling friction stops it rolling: the
        engines model that contact apart (MuJoCo's condim 6, no PyBullet friction anchor)."""
        return self.kind == "sphere"

    @property
    def half_extents(self) -> tuple[float, ...]:
        """MJCF-style size: box half extents, (radius, half height), (radius,)."""
        if self.kind in ("box", "mesh"):
            return tuple(s / 2 for s in self.size)
        if self.kind == "cylinder":
            return (self.size[0], self.size[1] / 2)
        return (self.size[0],)

    def inertia(self) -> tuple[float, float, float]:
        m = self.mass
        if self.kind == "sphere":
            i = 0.4 * m * self.size[0] ** 2
            return (i, i, i)
        if self.kind == "cylinder":
            r, h = self.size
            side = m * (3 * r * r + h * h) / 12
            return (side, side, m * r * r / 2)
        a, b, c = self.size
        return (m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12)


@dataclass(frozen=True)
class Scene:
    object: Body | None
    obstacles: tuple[Body, ...] = ()
    table: bool = True  # False: free space, for moving joints through their whole range


def box_scene(size: float = 0.05, xy: tuple[float, float] = (0.125, 0.0), mass: float = DEFAULT_WEIGHT) -> Scene:
    """A cube of `size` resting on the table: what `atd robots test` grasps."""
    pose = np.eye(4)
    pose[:3, 3] = (xy[0], xy[1], size / 2)
    return Scene(Body("object", "box", (size, size, size), pose, mass, DEFAULT_FRICTION))


def scene_from_task(task: Task, atd_file: Path) -> Scene:
    """The object and obstacles of a task; a mesh `shape` is looked up next to the ATD."""
    info = task.object
    body = None
    if info is not None:
        kind = (info.object_class or ObjectClass.BOX).value
        size = info.effective_size
        mesh = None
        if info.shape is not None:
            mesh = real_path(atd_file.parent / info.shape)
            where = f"{atd_file}: <object> shape '{info.shape}'"
            if not mesh.exists():  # a directory or a FIFO too: check_mesh says what it is
                raise SceneError(f"{where}: no such file {mesh}; put the mesh next to the ATD or fix the path")
            try:
                check_mesh(mesh)
            except MeshError as exc:
                raise SceneError(f"{where}: {exc}") from None
            kind = "mesh"
            size = _box_size(info)
        if info.pose is not None:
            pose = info.pose.as_array()
        else:  # resting on the table in the middle of the work area
            pose = np.eye(4)
            pose[:3, 3] = (0.125, 0.0, info.half_height)
        body = Body(
            "object", kind, tuple(size), pose,
            info.weight if info.weight is not None else DEFAULT_WEIGHT,
            info.friction if info.friction is not None else DEFAULT_FRICTION,
            mesh,
        )
    obstacles = []
    if task.environment is not None:
        for i, obstacle in enumerate(task.environment.obstacles):
            pose = np.eye(4)
            pose[:3, 3] = obstacle.position
            obstacles.append(Body(f"obstacle{i}", "box", obstacle.size or DEFAULT_OBSTACLE_SIZE, pose, 1.0, DEFAULT_FRICTION))
    return Scene(body, tuple(obstacles))


def _box_size(info) -> tuple[float, float, float]:
    """A bounding box for a mesh object's inertia: its class size as a box."""
    return bounding_box((info.object_class or ObjectClass.BOX).value, info.effective_size)


def bounding_box(kind: str, size: tuple[float, ...]) -> tuple[float, float, float]:
    """Full x, y, z lengths of the box around a body of `kind` and `size` (see `Body`)."""
    if kind in ("box", "mesh"):
        return (size[0], size[1], size[2])
    if kind == "cylinder":
        return (2 * size[0], 2 * size[0], size[1])
    return (2 * size[0],) * 3
