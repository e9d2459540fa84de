"""What a recording holds, and how a sample becomes its messages.

The control loop copies each sample's numbers into one row of floats (`Layout` says where
each reading sits); the writer process (atd/runtime/recording_writer.py) turns rows into
the JSON messages below. Splitting it so keeps the JSON encoding and the MCAP writing, most
of what recording costs, off the control loop.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import Any, Iterator

import numpy as np
import orjson

from atd.runtime.arbitrator import RobotCommand
from atd.sim.models import matrix_to_quat
from primitives.robot import Readings

PROFILE = "atd"
RECORDING_FORMAT = 1  # the channels and fields below; a reader refuses another
CLOCK = "atd.clock"  # metadata: the wall clock (ns since 1970) at simulated 0, the origin of every log time
DEFAULT_RATE = 100.0  # Hz of simulated time
DECIMALS = 6  # as the trace: micro-units (um, uN, urad) are finer than any sensor here tells apart,
# and a short number costs JSON about half of what a full-precision one does

JOINTS = ("arm_q", "arm_dq", "arm_effort", "hand_q", "hand_dq", "hand_effort")  # fields of /sensors
COMMANDED = ("twist", "joint_velocity", "hand_values")  # vectors of /commands

_NUMBERS = {"type": "array", "items": {"type": "number"}}
_VECTOR3 = {"type": "object", "properties": {a: {"type": "number"} for a in "xyz"}}
_POSE = {"type": "object", "properties": {
    "position": _VECTOR3, "orientation": {"type": "object", "properties": {a: {"type": "number"} for a in "xyzw"}}}}


def schemas_of(layout: Layout) -> dict[str, dict[str, Any]]:
    """The JSON Schemas of one robot's recording, in the form Foxglove's JSON Schema reader
    takes (it drops a whole channel at a field of two types, a oneOf other than numbers or an
    object without properties): the pads and objects named as this recording has them; the
    fields that may be null (`range`, a pad's `taxels`, the commanded vectors) left
    undeclared, as JSON Schema allows, rather than declared in a form Foxglove refuses."""
    return {
        "atd.Sensors": {"type": "object", "properties": {
            **{k: _NUMBERS for k in JOINTS},
            "tcp": _POSE,
            "wrench": {"type": "object", "properties": {"force": _VECTOR3, "torque": _VECTOR3}},
            "pads": {"type": "object", "properties": {
                name: {"type": "object", "properties": {"force": {"type": "number"}}} for name, _ in layout.pads}}}},
        "atd.Commands": {"type": "object", "properties": {"hand_modes": {"type": "array", "items": {"type": "string"}}}},
        "atd.State": {"type": "object", "properties": {"path": {"type": "string"}, "atd": {"type": "string"}}},
        "atd.TraceRecord": {"type": "object", "properties": {"type": {"type": "string"}, "state": {"type": "string"}}},
        "atd.Truth": {"type": "object", "properties": {
            **({"object": _POSE} if layout.objects else {}),
            "objects": {"type": "object", "properties": {name: _POSE for name in layout.objects}},
            "tcp": _POSE,
            "pad_contacts": {"type": "array", "items": {"type": "object", "properties": {
                "pad": {"type": "string"}, "x": {"type": "number"}, "y": {"type": "number"},
                "force": {"type": "number"}}}}}},
    }


#: topic, schema, ground truth
CHANNELS = (("/sensors", "atd.Sensors", False), ("/commands", "atd.Commands", False),
            ("/task/state", "atd.State", False), ("/task/trace", "atd.TraceRecord", False),
            ("/truth", "atd.Truth", True))

_POSE_SIZE = 16  # a 4x4 matrix, row by row


@dataclass(frozen=True)
class Layout:
    """Where each number of a sample sits in its row, for one robot."""

    arm: int  # arm joints
    hand: int  # hand DOFs
    pads: tuple[tuple[str, tuple[int, int] | None], ...]  # each pad's name and taxel array (rows, cols)
    objects: tuple[str, ...]  # every object's name; the first is the task's own ("object")
    joints: int = 0  # the robot's true joint positions (arm, then hand joints), for the 3D scene

    @cached_property
    def fields(self) -> dict[str, slice]:
        sizes = [("t", 1), *((f"arm_{k}", self.arm) for k in ("q", "dq", "effort")),
                 *((f"hand_{k}", self.hand) for k in ("q", "dq", "effort")),
                 ("tcp", _POSE_SIZE), ("wrench", 6), ("pad_force", len(self.pads)),
                 *((f"taxels {name}", rows * cols) for name, (rows, cols) in self.taxel_pads),
                 ("range", 1), ("twist", 6), ("joint_velocity", self.arm), ("hand_values", self.hand),
                 ("true_tcp", _POSE_SIZE), ("objects", _POSE_SIZE * len(self.objects)), ("true_joints", self.joints)]
        found, start = {}, 0
        for name, size in sizes:
            found[name] = slice(start, start + size)
            start += size
        found["object"] = slice(found["objects"].start, found["objects"].start + (_POSE_SIZE if self.objects else 0))
        return found

    @property
    def taxel_pads(self) -> list[tuple[str, tuple[int, int]]]:
        return [(name, shape) for name, shape in self.pads if shape is not None]

    def row(self, t: float, r: Readings, command: RobotCommand | None, true_tcp: np.ndarray,
            object_poses: list[np.ndarray], true_joints: np.ndarray) -> list[np.ndarray | tuple[float]]:
        """The pieces of one sample's row, in the order of `fields` (NaN for what is None)."""
        twist, joint_velocity, hand_values = (None, None, None) if command is None else (
            command.twist, command.joint_velocity, command.hand_values)
        missing = self._missing
        parts = [(t,), r.arm_q, r.arm_dq, r.arm_effort, r.hand_q, r.hand_dq, r.hand_effort, r.tcp.ravel(), r.wrench,
                 r.pad_force, *(r.taxels[name].ravel() for name, _ in self.taxel_pads),
                 missing["range"] if r.range is None else (r.range,),
                 missing["twist"] if twist is None else twist,
                 missing["joint_velocity"] if joint_velocity is None else joint_velocity,
                 missing["hand_values"] if hand_values is None else hand_values, true_tcp.ravel()]
        return parts + [pose.ravel() for pose in object_poses] + [true_joints]

    @cached_property
    def _missing(self) -> dict[str, np.ndarray]:
        return {name: np.full(self.fields[name].stop - self.fields[name].start, np.nan)
                for name in ("range", "twist", "joint_velocity", "hand_values")}

    @property
    def width(self) -> int:
        return self.fields["true_joints"].stop


def encode(message: dict[str, Any]) -> bytes:
    """JSON of a message (numpy arrays written natively, in trace records too)."""
    return orjson.dumps(message, option=orjson.OPT_SERIALIZE_NUMPY)


def _pose(matrix: np.ndarray, rounded: list[float]) -> dict[str, Any]:
    """A 4x4 pose (and the same, rounded, row by row) as a position and a unit quaternion,
    in the field names Foxglove reads."""
    w, x, y, z = (round(q, DECIMALS) for q in matrix_to_quat(matrix[:3, :3]))
    return {"position": _xyz(rounded[3], rounded[7], rounded[11]), "orientation": {"x": x, "y": y, "z": z, "w": w}}


def _xyz(x: float, y: float, z: float) -> dict[str, float]:
    return {"x": x, "y": y, "z": z}


def _vector(values: list[float]) -> list[float] | None:
    """A command vector, None where no controller gave one (the control loop sent NaN)."""
    return None if values and math.isnan(values[0]) else values


#: What the control loop sends besides a row: the state's (path, ATD state), the hand
#: modes commanded (None before the first command), and the true pad contacts (each one's
#: pad index, point in the pad's frame, normal force). Plain tuples and lists: pickled to
#: the writer, they cost a fraction of what arrays or a dataclass would.
Sample = tuple[tuple[str, str], "list[str] | None", tuple[list[int], list[list[float]], list[float]]]


def _contacts(pad_names: list[str], pads: list[int], points: list[list[float]],
              forces: list[float]) -> list[dict[str, Any]]:
    if not pads:
        return []
    xy, force = np.round(points, DECIMALS).tolist(), np.round(forces, DECIMALS).tolist()
    return [{"pad": pad_names[k], "x": x, "y": y, "force": f} for k, (x, y), f in zip(pads, xy, force)]


def messages(layout: Layout, block: np.ndarray, samples: list[Sample],
             traces: list[tuple[int, dict[str, Any]]]) -> Iterator[tuple[str, int, dict[str, Any]]]:
    """(topic, time in ns, message) for each row of `block`, and each trace record before the
    row whose index it comes with (an index past the last row: after them)."""
    rounded = block.round(DECIMALS)
    f = layout.fields
    column = {name: rounded[:, f[name]].tolist()
              for name in (*JOINTS, "wrench", "pad_force", *COMMANDED, "tcp", "true_tcp", "objects")}
    taxels = {name: rounded[:, f[f"taxels {name}"]].reshape(len(block), *shape).tolist()
              for name, shape in layout.taxel_pads}
    # Shapes spelt out: a block may have no rows (a run's trace records after its last tick).
    poses = {name: block[:, f[name]].reshape(len(block), block[:, f[name]].shape[1] // 4, 4)
             for name in ("tcp", "true_tcp", "objects")}
    pad_names = [name for name, _ in layout.pads]
    pending = iter(traces)
    trace = next(pending, None)
    for i, ((state, hand_modes, contacts), t, distance) in enumerate(
            zip(samples, block[:, 0].tolist(), rounded[:, f["range"]][:, 0].tolist())):
        while trace is not None and trace[0] <= i:
            yield "/task/trace", int(round(trace[1]["t"] * 1e9)), trace[1]
            trace = next(pending, None)
        ns = int(round(t * 1e9))
        force, torque = column["wrench"][i][:3], column["wrench"][i][3:]
        yield "/sensors", ns, {
            **{name: column[name][i] for name in JOINTS},
            "tcp": _pose(poses["tcp"][i], column["tcp"][i]), "wrench": {"force": _xyz(*force), "torque": _xyz(*torque)},
            "pads": {name: {"force": pad_force, "taxels": taxels[name][i] if name in taxels else None}
                     for name, pad_force in zip(pad_names, column["pad_force"][i])},
            "range": distance if math.isfinite(distance) else None}
        if hand_modes is not None:
            yield "/commands", ns, {**{name: _vector(column[name][i]) for name in COMMANDED}, "hand_modes": hand_modes}
        yield "/task/state", ns, {"path": state[0], "atd": state[1]}
        objects = {name: _pose(poses["objects"][i][4 * k:4 * k + 4], column["objects"][i][16 * k:16 * k + 16])
                   for k, name in enumerate(layout.objects)}
        yield "/truth", ns, {
            "object": next(iter(objects.values()), None), "objects": objects,
            "tcp": _pose(poses["true_tcp"][i], column["true_tcp"][i]),
            "pad_contacts": _contacts(pad_names, *contacts)}
    for _, record in ([trace] if trace else []) + list(pending):
        yield "/task/trace", int(round(record["t"] * 1e9)), record
