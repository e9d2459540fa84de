"""What Foxglove's 3D panel draws from a recording: the simulator's frames (world, each
arm's base, links and TCP, each object) as `foxglove.FrameTransforms`, the bodies on
them (table, obstacles, containers, objects, the robot's link shapes) as one
`foxglove.SceneUpdate` of frame-locked entities, and the TCP the robot believes in as a
`foxglove.PoseInFrame`.

Foxglove knows these schemas by name; the JSON Schemas below are written from its schema
reference (JSON encoding: times as {sec, nsec}, bytes as base64). Frames and bodies are
the simulator's truth (channel metadata `ground_truth: true`), the believed TCP is not.
They are written at SCENE_RATE Hz of simulated time at most, whatever the recording's
rate: enough for a smooth picture, a fraction of the file's size.
"""

from __future__ import annotations

import base64
from dataclasses import dataclass
from typing import Any, Iterator

import numpy as np

from atd.runtime.recording_format import DECIMALS
from atd.sim.models import matrix_to_quat
from atd.sim.scene import COLOURS, TABLE_CENTRE, TABLE_HALF, Body, Scene
from factories.description import RobotDescription, Shape

SCENE_RATE = 25.0  # Hz of simulated time: transforms and the believed TCP
SCENE_REPEAT = 1.0  # s: the scene's entities again, so a viewer that seeks finds them near
ROOT = "world"
BASE = "base"  # the robot's base; its links are "link/NAME", the objects "object/NAME": no name clashes
TCP = "tcp"

_TIME = {"type": "object", "title": "time", "properties": {
    "sec": {"type": "integer", "minimum": 0}, "nsec": {"type": "integer", "minimum": 0, "maximum": 999_999_999}}}
_VECTOR3 = {"type": "object", "properties": {a: {"type": "number"} for a in "xyz"}}
_QUATERNION = {"type": "object", "properties": {a: {"type": "number"} for a in "xyzw"}}
_POSE = {"type": "object", "properties": {"position": _VECTOR3, "orientation": _QUATERNION}}
_COLOR = {"type": "object", "properties": {c: {"type": "number", "minimum": 0, "maximum": 1} for c in "rgba"}}
_SIZED = {"type": "object", "properties": {"pose": _POSE, "size": _VECTOR3, "color": _COLOR}}
_CYLINDER = {"type": "object", "properties": {**_SIZED["properties"], "bottom_scale": {"type": "number"},
                                              "top_scale": {"type": "number"}}}
_MODEL = {"type": "object", "properties": {
    "pose": _POSE, "scale": _VECTOR3, "color": _COLOR, "override_color": {"type": "boolean"},
    "url": {"type": "string"}, "media_type": {"type": "string"},
    "data": {"type": "string", "contentEncoding": "base64"}}}
_ENTITY = {"type": "object", "title": "foxglove.SceneEntity", "properties": {
    "timestamp": _TIME, "frame_id": {"type": "string"}, "id": {"type": "string"},
    "lifetime": {**_TIME, "title": "duration"}, "frame_locked": {"type": "boolean"},
    "metadata": {"type": "array", "items": {"type": "object", "properties": {
        "key": {"type": "string"}, "value": {"type": "string"}}}},
    "cubes": {"type": "array", "items": _SIZED}, "spheres": {"type": "array", "items": _SIZED},
    "cylinders": {"type": "array", "items": _CYLINDER}, "models": {"type": "array", "items": _MODEL}}}
# Only the primitives written are declared: Foxglove's JSON Schema reader (Studio 1.48) drops the
# whole channel at an array without `items`, and fills absent primitive lists with [] itself.
_TRANSFORM = {"type": "object", "title": "foxglove.FrameTransform", "properties": {
    "timestamp": _TIME, "parent_frame_id": {"type": "string"}, "child_frame_id": {"type": "string"},
    "translation": _VECTOR3, "rotation": _QUATERNION}}
SCHEMAS: dict[str, dict[str, Any]] = {
    "foxglove.FrameTransforms": {"type": "object", "title": "foxglove.FrameTransforms", "properties": {
        "transforms": {"type": "array", "items": _TRANSFORM}}},
    "foxglove.SceneUpdate": {"type": "object", "title": "foxglove.SceneUpdate", "properties": {
        "deletions": {"type": "array", "items": {"type": "object", "properties": {
            "timestamp": _TIME, "type": {"type": "integer", "enum": [0, 1]}, "id": {"type": "string"}}}},
        "entities": {"type": "array", "items": _ENTITY}}},
    "foxglove.PoseInFrame": {"type": "object", "title": "foxglove.PoseInFrame", "properties": {
        "timestamp": _TIME, "frame_id": {"type": "string"}, "pose": _POSE}},
}
#: topic, schema, ground truth
CHANNELS = (("/truth/tf", "foxglove.FrameTransforms", True), ("/truth/scene", "foxglove.SceneUpdate", True),
            ("/tcp", "foxglove.PoseInFrame", False))
_MEDIA = {".stl": "model/stl", ".obj": "model/obj"}


@dataclass(frozen=True)
class Arm:
    """One arm in the world: the prefix of its frames ("" for the arm recorded, "ARM/" for
    the others of a two-arm task), its description (for the links' poses from its true
    joint positions) and the order of those positions in a row."""

    prefix: str
    description: RobotDescription
    joints: tuple[str, ...]

    def link_frame(self, link: str | None) -> str:
        return f"{self.prefix}link/{link}" if link else f"{self.prefix}{BASE}"


@dataclass(frozen=True)
class Frames:
    """What the writer process needs to draw a run: the arms, and the scene's entities,
    built once."""

    arms: tuple[Arm, ...]
    objects: tuple[str, ...]  # the order of the object poses in a row
    entities: tuple[dict[str, Any], ...]  # without timestamps


def object_frame(name: str) -> str:
    return f"object/{name}"


def frames_of(arms: tuple[Arm, ...], scene: Scene) -> Frames:
    """The frames and entities of `arms` in `scene`."""
    entities = [_entity(arm.link_frame(link.name), f"{arm.prefix}link {link.name}", link.visuals or link.shapes)
                for arm in arms for link in arm.description.links]
    if scene.table:
        table = np.eye(4)
        table[:3, 3] = TABLE_CENTRE
        entities.append(_body_entity(ROOT, "table", Body("table", "box", tuple(2 * h for h in TABLE_HALF), table, 0, 0),
                                     COLOURS["table"], table))
    fixed = [(b, COLOURS["obstacle"]) for b in scene.obstacles]
    fixed += [(part, COLOURS["container"]) for c in scene.containers for part in c.parts()]
    entities += [_body_entity(ROOT, body.name, body, colour, body.pose) for body, colour in fixed]
    entities += [_body_entity(object_frame(b.name), f"object {b.name}", b, COLOURS["object"], np.eye(4))
                 for b in scene.objects]
    return Frames(arms, tuple(b.name for b in scene.objects), tuple(entities))


def _entity(frame: str, name: str, shapes: tuple[Shape, ...]) -> dict[str, Any]:
    """A link's shapes, each at its origin in the link's frame."""
    found: dict[str, list[dict[str, Any]]] = {"cubes": [], "spheres": [], "cylinders": [], "models": []}
    for shape in shapes:
        at, colour = shape.origin.matrix(), _colour(shape.rgba)
        if shape.kind == "box":
            found["cubes"].append(_sized(at, [2 * s for s in shape.size], colour))
        elif shape.kind == "sphere":
            found["spheres"].append(_sized(at, [2 * shape.size[0]] * 3, colour))
        elif shape.kind in ("cylinder", "capsule"):
            radius, half = shape.size[:2]
            found["cylinders"].append({**_sized(at, [2 * radius, 2 * radius, 2 * half], colour),
                                       "bottom_scale": 1.0, "top_scale": 1.0})
            if shape.kind == "capsule":  # Foxglove has no capsule: a cylinder and its two round ends
                for end in (-half, half):
                    cap = at @ _translation(0.0, 0.0, end)
                    found["spheres"].append(_sized(cap, [2 * radius] * 3, colour))
        elif shape.mesh is not None:
            found["models"].append(_model(shape.mesh, at, shape.size, colour))
    return _wrap(frame, name, found)


def _body_entity(frame: str, name: str, body: Body, rgba: tuple[float, ...], at: np.ndarray) -> dict[str, Any]:
    """A scene body drawn at `at` in `frame` (its own frame for an object that moves)."""
    colour = _colour(rgba)
    found: dict[str, list[dict[str, Any]]] = {"cubes": [], "spheres": [], "cylinders": [], "models": []}
    if body.kind == "box":
        found["cubes"].append(_sized(at, list(body.size), colour))
    elif body.kind == "sphere":
        found["spheres"].append(_sized(at, [2 * body.size[0]] * 3, colour))
    elif body.kind == "cylinder":
        radius, height = body.size
        found["cylinders"].append({**_sized(at, [2 * radius, 2 * radius, height], colour),
                                   "bottom_scale": 1.0, "top_scale": 1.0})
    elif body.mesh is not None:
        placed = at if body.mesh_frame is None else at @ body.mesh_frame
        found["models"].append(_model(body.mesh, placed, body.mesh_scale, colour))
    return _wrap(frame, name, found)


def _wrap(frame: str, name: str, primitives: dict[str, list[dict[str, Any]]]) -> dict[str, Any]:
    return {"frame_id": frame, "id": name, "lifetime": {"sec": 0, "nsec": 0}, "frame_locked": True,
            "metadata": [], **primitives}


def _model(mesh: Any, at: np.ndarray, scale: tuple[float, ...], colour: dict[str, float]) -> dict[str, Any]:
    """A mesh file carried in the message itself: the recording opens anywhere."""
    return {"pose": pose_of(at), "scale": _xyz(*scale), "color": colour, "override_color": True, "url": "",
            "media_type": _MEDIA.get(mesh.suffix.lower(), "model/stl"),
            "data": base64.b64encode(mesh.read_bytes()).decode()}


def _sized(at: np.ndarray, size: list[float], colour: dict[str, float]) -> dict[str, Any]:
    return {"pose": pose_of(at), "size": _xyz(*size), "color": colour}


def _colour(rgba: tuple[float, ...]) -> dict[str, float]:
    return dict(zip("rgba", (float(c) for c in rgba)))


def _translation(x: float, y: float, z: float) -> np.ndarray:
    m = np.eye(4)
    m[:3, 3] = (x, y, z)
    return m


def _xyz(x: float, y: float, z: float) -> dict[str, float]:
    return {"x": round(float(x), DECIMALS), "y": round(float(y), DECIMALS), "z": round(float(z), DECIMALS)}


def pose_of(matrix: np.ndarray) -> dict[str, Any]:
    """A 4x4 pose as Foxglove's position and unit quaternion."""
    w, x, y, z = (round(q, DECIMALS) for q in matrix_to_quat(matrix[:3, :3]))
    return {"position": _xyz(*matrix[:3, 3]), "orientation": {"x": x, "y": y, "z": z, "w": w}}


def _time(ns: int) -> dict[str, int]:
    return {"sec": ns // 1_000_000_000, "nsec": ns % 1_000_000_000}


class SceneWriter:
    """The writer process's drawing of a run: from each row's true joint positions, object
    poses and believed TCP, the messages of CHANNELS at SCENE_RATE."""

    def __init__(self, frames: Frames, zero: int = 0) -> None:
        self.frames = frames
        self.zero = zero  # ns of wall clock at simulated 0: the messages' own timestamps are wall-clock times
        self.next_tf = 0.0
        self.next_scene = 0.0

    def messages(self, t: float, joints: np.ndarray, objects: np.ndarray,
                 believed_tcp: np.ndarray) -> Iterator[tuple[str, int, dict[str, Any]]]:
        """(topic, simulated time in ns, message) due at `t` s: none between SCENE_RATE's ticks."""
        if t + 1e-9 < self.next_tf:
            return
        self.next_tf = t + 1.0 / SCENE_RATE
        ns = int(round(t * 1e9))
        stamp = _time(self.zero + ns)
        if t + 1e-9 >= self.next_scene:
            self.next_scene = t + SCENE_REPEAT
            yield "/truth/scene", ns, {"deletions": [], "entities": [{"timestamp": stamp, **e}
                                                                     for e in self.frames.entities]}
        yield "/truth/tf", ns, {"transforms": [
            {"timestamp": stamp, "parent_frame_id": parent, "child_frame_id": child,
             "translation": pose["position"], "rotation": pose["orientation"]}
            for parent, child, pose in self._transforms(joints, objects)]}
        yield "/tcp", ns, {"timestamp": stamp, "frame_id": ROOT, "pose": pose_of(believed_tcp)}

    def _transforms(self, joints: np.ndarray, objects: np.ndarray) -> Iterator[tuple[str, str, dict[str, Any]]]:
        """(parent, child, pose of the child in the parent) of every frame."""
        values = joints.tolist()
        for arm in self.frames.arms:
            d = arm.description
            base = d.base.matrix()
            yield ROOT, arm.link_frame(None), pose_of(base)
            poses = d.link_poses(dict(zip(arm.joints, values[:len(arm.joints)])))
            values = values[len(arm.joints):]
            for link in d.links:
                parent = poses[link.parent] if link.parent else base
                yield arm.link_frame(link.parent), arm.link_frame(link.name), pose_of(
                    np.linalg.solve(parent, poses[link.name]))
            yield arm.link_frame(d.tcp.link), f"{arm.prefix}{TCP}", pose_of(d.tcp.origin.matrix())
        for k, name in enumerate(self.frames.objects):
            yield ROOT, object_frame(name), pose_of(objects[16 * k:16 * k + 16].reshape(4, 4))
