"""The world a robot works in: by default what an ATD's `<object>` and `<environment>`
say, or what a world file says is true (atd/sim/world.py).

Everything is in the ATD world frame: the table top is the plane z = 0 and x points away
from the robot. Objects are free to move; obstacles and containers are fixed.
"""

from __future__ import annotations

import builtins
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import numpy as np

from atd.model import ObjectClass, ObjectInfo, Task
from atd.model.files import real_path
from atd.model.meshcheck import MeshError, check_mesh
from atd.sim.thread import Thread

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
WORKSPACE_CAMERA = "workspace"  # that view's name among the cameras a video can be rendered from
# What is not the robot, as both engines paint it (red, green, blue, opacity).
COLOURS = {"table": (0.7, 0.55, 0.4, 1.0), "object": (0.2, 0.7, 0.3, 1.0), "obstacle": (0.4, 0.4, 0.8, 1.0),
           "container": (0.8, 0.65, 0.45, 1.0), "cap": (0.85, 0.2, 0.2, 1.0)}


class SceneError(ValueError):
    """The ATD describes something the simulator cannot build; the message says what to fix."""


@dataclass(frozen=True)
class Body:
    """A simulated object. `size` follows `atd.model.vocabulary.SIZE_LAYOUT` for the
    class (box x y z full lengths, cylinder radius height, sphere radius); for a mesh it is
    the bounding box used for the inertia.

    A mesh file is scaled by `mesh_scale` in its own axes, then placed by `mesh_frame` in
    the body's frame. The engines collide with the convex hull of the mesh or, for a
    concave mesh, with each of its convex `mesh_parts` (files in the mesh's own frame).

    A body with a `thread` is a bottle or jar with a screw cap (atd/sim/thread.py): `size`
    and `pose` are the whole object's, `mass` includes the cap's."""

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
    thread: Thread | None = None

    @property
    def own_mass(self) -> float:
        """The mass of the body itself: without its cap, which the engines build apart."""
        return self.mass - (self.thread.cap_mass if self.thread is not None else 0.0)

    @property
    def collision_meshes(self) -> tuple[Path, ...]:
        """The files the engines build the object's collision geometry from."""
        return self.mesh_parts or ((self.mesh,) if self.mesh is not None else ())

    @property
    def rolls(self) -> bool:
        """It can rest on the table at one point or along one line (a ball; a cylinder knocked
        onto its side), so only rolling friction stops it rolling: the engines model that
        contact apart (MuJoCo's condim 6, no PyBullet friction anchor); without it a lying
        cylinder rolled on at constant or growing speed (docs/robust-grasp.md, `pbw33`)."""
        return self.kind in ("sphere", "cylinder")

    @property
    def half_extents(self) -> tuple[float, ...]:
        """MJCF-style size: box half extents, (radius, half height), (radius,)."""
        if self.kind in ("box", "mesh"):
            return tuple(s / 2 for s in self.size)
        if self.kind == "cylinder":
            return (self.size[0], self.size[1] / 2)
        return (self.size[0],)

    def inertia(self) -> tuple[float, float, float]:
        """Of `own_mass` spread over the body's shape."""
        m = self.own_mass
        if self.kind == "sphere":
            i = 0.4 * m * self.size[0] ** 2
            return (i, i, i)
        if self.kind == "cylinder":
            r, h = self.size
            side = m * (3 * r * r + h * h) / 12
            return (side, side, m * r * r / 2)
        a, b, c = self.size
        return (m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12)


#: Of a container, how far above its rim an object's centre may lie and still count as in
#: it: one piled on others pokes out of the box; one carried off is well above this.
PILE_HEIGHT = 0.1  # m


@dataclass(frozen=True)
class Container:
    """An open-topped box standing on the table, fixed: a floor and four walls. `pose` is the
    centre of its floor's underside, `size` its outer lengths (x, y, z in its own frame),
    `wall` the thickness of walls and floor."""

    name: str
    pose: np.ndarray  # 4x4
    size: tuple[float, float, float]
    wall: float = 0.01
    friction: float = DEFAULT_FRICTION

    def parts(self) -> tuple[Body, ...]:
        """The floor and the four walls, as fixed boxes in the world."""
        sx, sy, sz = self.size
        t = self.wall
        boxes = [("floor", (0.0, 0.0, t / 2), (sx, sy, t))]
        for sign in (1, -1):  # the x walls run the whole length; the y walls fit between them
            boxes.append((f"wall_x{'+' if sign > 0 else '-'}", (sign * (sx - t) / 2, 0.0, sz / 2), (t, sy, sz)))
            boxes.append((f"wall_y{'+' if sign > 0 else '-'}", (0.0, sign * (sy - t) / 2, sz / 2), (sx - 2 * t, t, sz)))
        placed = []
        for part, centre, size in boxes:
            local = np.eye(4)
            local[:3, 3] = centre
            placed.append(Body(f"{self.name}_{part}", "box", size, self.pose @ local, 1.0, self.friction))
        return tuple(placed)

    def inner_corners(self) -> tuple[np.ndarray, np.ndarray]:
        """(low, high) corners of the space inside, in the container's own frame."""
        sx, sy, sz = self.size
        t = self.wall
        return np.array([-sx / 2 + t, -sy / 2 + t, t]), np.array([sx / 2 - t, sy / 2 - t, sz])

    def inner_bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """(low, high) corners of the world-axis box around the space inside."""
        low, high = self.inner_corners()
        corners = np.array([[x, y, z, 1.0] for x in (low[0], high[0]) for y in (low[1], high[1])
                            for z in (low[2], high[2])]) @ self.pose.T
        return corners[:, :3].min(axis=0), corners[:, :3].max(axis=0)

    def gap_to_walls(self, body: Body, pose: np.ndarray) -> float:
        """How far the body at `pose` keeps from the inner walls, along this container's x and
        y (negative: through a wall); by `half_extent`, so a box's and a mesh's is a lower bound."""
        local = np.linalg.solve(self.pose, pose)
        low, high = self.inner_corners()
        gaps = []
        for k, axis in enumerate(np.eye(3)[:2]):
            reach = half_extent(body.kind, body.size, local[:3, :3], axis)
            gaps += [local[k, 3] - reach - low[k], high[k] - local[k, 3] - reach]
        return min(gaps)

    def holds(self, point: np.ndarray) -> bool:
        """Whether a point (an object's centre, world frame) is in the container: over its
        floor, inside its walls, and no higher than PILE_HEIGHT above its rim."""
        local = np.linalg.solve(self.pose, np.append(np.asarray(point, float), 1.0))[:3]
        low, high = self.inner_corners()
        high = high + (0.0, 0.0, PILE_HEIGHT)
        return bool(np.all(local >= low) and np.all(local <= high))


_set = builtins.object.__setattr__  # a frozen dataclass sets its own fields this way


@dataclass(frozen=True, init=False)
class Scene:
    """What the engines build: free `objects` (names unique), fixed `obstacles` and
    `containers`, the table. `settle`: let gravity bring the objects to rest before the
    run's clock starts (objects a world file dropped or stacked)."""

    objects: tuple[Body, ...]
    obstacles: tuple[Body, ...]
    table: bool  # False: free space, for moving joints through their whole range
    containers: tuple[Container, ...]
    settle: bool

    def __init__(self, object: Body | None = None, obstacles: tuple[Body, ...] = (), table: bool = True, *,
                 objects: tuple[Body, ...] = (), containers: tuple[Container, ...] = (), settle: bool = False):
        """`object`, when given, is the first of `objects` (the task's own): `Scene(body)` and
        `dataclasses.replace(scene, object=body)` make or change a one-object world."""
        bodies = tuple(objects)
        if object is not None:
            bodies = (object, *bodies[1:])
        names = [b.name for b in bodies] + [c.name for c in containers]
        if len(set(names)) != len(names):
            twice = sorted({n for n in names if names.count(n) > 1})
            raise ValueError(f"objects and containers need names of their own; {', '.join(twice)} stand twice")
        _set(self, "objects", bodies)
        _set(self, "obstacles", tuple(obstacles))
        _set(self, "table", table)
        _set(self, "containers", tuple(containers))
        _set(self, "settle", settle)

    @property
    def object(self) -> Body | None:
        """The first object (the task's own), or None."""
        return self.objects[0] if self.objects else None

    def container(self, name: str) -> Container:
        """The container called `name`; LookupError naming the ones there are."""
        for container in self.containers:
            if container.name == name:
                return container
        known = ", ".join(c.name for c in self.containers) or "none"
        raise LookupError(f"no container '{name}' in this world; its containers: {known}")


def box_scene(size: float = 0.05, xy: tuple[float, float] = (0.125, 0.0), mass: float = DEFAULT_WEIGHT) -> Scene:
    """A cube of `size` resting on the table: what `atd robots test` grasps."""
    pose = np.eye(4)
    pose[:3, 3] = (xy[0], xy[1], size / 2)
    return Scene(Body("object", "box", (size, size, size), pose, mass, DEFAULT_FRICTION))


def scene_from_task(task: Task, atd_file: Path) -> Scene:
    """The objects, obstacles and containers of a task, each object by its name (the one
    unnamed object: 'object'); a mesh `shape` is looked up next to the ATD."""
    bodies = tuple(object_body(info, name, atd_file) for name, info in task.objects.items())
    containers = tuple(Container(c.name, c.pose.as_array(), c.size, c.wall) for c in task.containers.values())
    obstacles = []
    if task.environment is not None:
        for i, obstacle in enumerate(task.environment.obstacles):
            pose = np.eye(4)
            pose[:3, 3] = obstacle.position
            obstacles.append(Body(f"obstacle{i}", "box", obstacle.size or DEFAULT_OBSTACLE_SIZE, pose, 1.0, DEFAULT_FRICTION))
    return Scene(objects=bodies, obstacles=tuple(obstacles), containers=containers)


def object_body(info: ObjectInfo, name: str, atd_file: Path) -> Body:
    """The body an ATD's `<object>` describes; without a pose, it rests on the table in the
    middle of the work area."""
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
    else:
        pose = np.eye(4)
        pose[:3, 3] = (0.125, 0.0, info.half_height)
    return Body(name, kind, tuple(size), pose,
                info.weight if info.weight is not None else DEFAULT_WEIGHT,
                info.friction if info.friction is not None else DEFAULT_FRICTION, mesh)


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


def half_extent(kind: str, size: tuple[float, ...], rotation: np.ndarray, axis: np.ndarray) -> float:
    """How far a body of `kind` and `size`, turned by `rotation`, reaches from its centre along
    the unit `axis`: exact for a sphere and a cylinder, by the turned bounding box for a box
    and a mesh (for a mesh, an upper bound)."""
    if kind == "sphere":
        return float(size[0])
    if kind == "cylinder":
        along = abs(float(rotation[:, 2] @ axis))  # the cylinder's own axis against `axis`
        return float(size[0] * np.sqrt(max(0.0, 1.0 - along * along)) + size[1] / 2 * along)
    return float(np.abs(rotation.T @ axis) @ (np.asarray(bounding_box(kind, size)) / 2))
