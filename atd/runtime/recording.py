"""A run's signals, recorded per tick into MCAP: what the robot's sensors read, what the
arbitrator commanded, where the task was, and the simulator's ground truth beside them.

MCAP with JSON schemas is what Foxglove and PlotJuggler open as is (and what ROS 2 bags
are), so a roboticist can plot pad forces against the wrist force with the tools they
already use. Times are simulated time, in nanoseconds. Topics under `/truth/` carry the
simulator's ground truth (channel metadata `ground_truth: true`): no primitive sees them.
"""

from __future__ import annotations

import io
import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import orjson
from mcap.writer import CompressionType, Writer

from atd.model.files import write_output
from atd.runtime.executor import Executor, Outcome
from atd.runtime.trace import Trace
from atd.sim.models import matrix_to_quat
from atd.sim.simrobot import SimRobot

PROFILE = "atd"
RECORDING_FORMAT = 1  # the channels and fields below; a reader refuses another
DEFAULT_RATE = 100.0  # Hz of simulated time

_NUMBERS = {"type": "array", "items": {"type": "number"}}
_MAYBE_NUMBERS = {"type": ["array", "null"], "items": {"type": "number"}}
_VECTOR3 = {"type": "object", "properties": {a: {"type": "number"} for a in "xyz"}}
_POSE = {"type": "object", "properties": {
    "position": _VECTOR3, "orientation": {"type": "object", "properties": {a: {"type": "number"} for a in "xyzw"}}}}
_PAD = {"type": "object", "properties": {"force": {"type": "number"},
                                         "taxels": {"type": ["array", "null"], "items": _NUMBERS}}}
_SCHEMAS: dict[str, dict[str, Any]] = {
    "atd.Sensors": {"type": "object", "properties": {
        **{k: _NUMBERS for k in ("arm_q", "arm_dq", "arm_effort", "hand_q", "hand_dq", "hand_effort")},
        "tcp": _POSE,
        "wrench": {"type": "object", "properties": {"force": _VECTOR3, "torque": _VECTOR3}},
        "pads": {"type": "object", "additionalProperties": _PAD},
        "range": {"type": ["number", "null"]}}},
    "atd.Commands": {"type": "object", "properties": {
        "twist": _MAYBE_NUMBERS, "joint_velocity": _MAYBE_NUMBERS, "hand_values": _MAYBE_NUMBERS,
        "hand_modes": {"type": "array", "items": {"type": "string"}}}},
    "atd.State": {"type": "object", "properties": {"path": {"type": "string"}, "atd": {"type": "string"}}},
    "atd.TraceRecord": {"type": "object", "properties": {"type": {"type": "string"}, "state": {"type": "string"}}},
    "atd.Truth": {"type": "object", "properties": {
        "object": {"oneOf": [_POSE, {"type": "null"}]}, "tcp": _POSE,
        "pad_contacts": {"type": "array", "items": {"type": "object", "properties": {
            "pad": {"type": "string"}, "x": {"type": "number"}, "y": {"type": "number"},
            "force": {"type": "number"}}}}}},
}


def quaternion(rotation: np.ndarray) -> dict[str, float]:
    """A rotation matrix as a unit quaternion, in the field names Foxglove reads."""
    w, x, y, z = (round(q, DECIMALS) for q in matrix_to_quat(rotation))
    return {"x": x, "y": y, "z": z, "w": w}


def _pose(matrix: np.ndarray) -> dict[str, Any]:
    return {"position": _xyz(matrix[:3, 3]), "orientation": quaternion(matrix[:3, :3])}


def _encode(message: dict[str, Any]) -> bytes:
    """JSON of a message whose arrays stay numpy arrays: orjson writes them natively, about a
    third of what the json module and `tolist` cost per sample (benchmarks/bench_record.py)."""
    return orjson.dumps(message, option=orjson.OPT_SERIALIZE_NUMPY)


def _xyz(v: np.ndarray) -> dict[str, float]:
    x, y, z = v.round(DECIMALS).tolist()
    return {"x": x, "y": y, "z": z}


DECIMALS = 6  # as the trace: micro-units (um, uN, urad) are finer than any sensor here tells apart,
# and a short number costs JSON about half of what a full-precision one does


def _list(v: np.ndarray | None) -> np.ndarray | None:
    return None if v is None else np.ascontiguousarray(v, dtype=np.float64).round(DECIMALS)


class Recording:
    """An observer of the executor: every `1/rate` s of simulated time (every tick when
    `rate` is None) it writes one message per channel; trace records as they happen."""

    def __init__(self, path: Path, robot: SimRobot, executor: Executor, trace: Trace,
                 has_object: bool, rate: float | None = DEFAULT_RATE, info: dict[str, str] | None = None,
                 attachments: dict[str, bytes] | None = None) -> None:
        self.path, self.robot, self.executor, self.trace = path, robot, executor, trace
        self.period = 0.0 if rate is None else 1.0 / rate
        self.next = 0.0
        self.traced = 0  # trace records written so far
        self.buffer = io.BytesIO()
        self.writer = Writer(self.buffer, compression=CompressionType.ZSTD)
        self.writer.start(profile=PROFILE, library="atd")
        schema_ids = {name: self.writer.register_schema(name, "jsonschema", json.dumps(s).encode())
                      for name, s in _SCHEMAS.items()}
        info_ = robot.info
        pads = [p.name for p in info_.hand.pads]

        def channel(topic: str, schema: str, truth: bool = False, **meta: str) -> int:
            metadata = {"ground_truth": "true" if truth else "false", **meta}
            return self.writer.register_channel(topic, "json", schema_ids[schema], metadata)

        self.channels = {
            "sensors": channel("/sensors", "atd.Sensors", arm_joints=" ".join(info_.arm_joints),
                               hand_dofs=" ".join(info_.hand.dofs), wrench_frame="hand"),
            "commands": channel("/commands", "atd.Commands"),
            "state": channel("/task/state", "atd.State"),
            "trace": channel("/task/trace", "atd.TraceRecord"),
            "truth": channel("/truth", "atd.Truth", truth=True),
        }
        self.pad_names = pads
        self.has_object = has_object
        self.sequence = 0
        for name, data in (info or {}).items():
            self.writer.add_metadata(name, {"value": data})
        for name, data in (attachments or {}).items():
            self.writer.add_attachment(0, 0, name, "application/xml", data)

    def _put(self, channel: int, time_ns: int, message: dict[str, Any]) -> None:
        self.sequence += 1
        self.writer.add_message(channel, time_ns, _encode(message), time_ns, self.sequence)

    def __call__(self, sim_time: float) -> None:
        self._trace_records()
        if sim_time + 1e-9 < self.next:
            return
        self.next = sim_time + self.period
        t = int(round(sim_time * 1e9))
        r = self.robot.read()
        c = self.channels
        self._put(c["sensors"], t, {
            "arm_q": _list(r.arm_q), "arm_dq": _list(r.arm_dq), "arm_effort": _list(r.arm_effort),
            "hand_q": _list(r.hand_q), "hand_dq": _list(r.hand_dq), "hand_effort": _list(r.hand_effort),
            "tcp": _pose(r.tcp), "wrench": {"force": _xyz(r.wrench[:3]), "torque": _xyz(r.wrench[3:])},
            "pads": {name: {"force": force, "taxels": _list(r.taxels.get(name))}
                     for name, force in zip(self.pad_names, _list(r.pad_force).tolist())},
            "range": None if r.range is None or math.isinf(r.range) else round(r.range, DECIMALS)})
        command = self.executor.command
        if command is not None:
            self._put(c["commands"], t, {
                "twist": _list(command.twist), "joint_velocity": _list(command.joint_velocity),
                "hand_values": _list(command.hand_values), "hand_modes": [str(m) for m in command.hand_modes]})
        visit = self.executor.machine.innermost().visit
        self._put(c["state"], t, {"path": visit.path, "atd": visit.atd})
        pads, points, forces = self.robot.true_pad_contacts()
        self._put(c["truth"], t, {
            "object": _pose(self.robot.object_pose()) if self.has_object else None,
            "tcp": _pose(self.robot.true_tcp()),
            "pad_contacts": [{"pad": self.pad_names[k], "x": x, "y": y, "force": f}
                             for k, (x, y), f in zip(pads.tolist(), _list(points).tolist(), _list(forces).tolist())]})

    def _trace_records(self) -> None:
        for record in self.trace.records[self.traced:]:
            t = int(round(record["t"] * 1e9))
            self._put(self.channels["trace"], t, record)
        self.traced = len(self.trace.records)

    def finish(self, outcome: Outcome) -> None:
        """Write the end of the run and the file, whole (OutputError when it cannot be)."""
        self._trace_records()
        self.writer.add_metadata("atd.outcome", {
            "succeeded": str(outcome.succeeded).lower(), "summary": outcome.summary,
            "end_state": outcome.end_state or "", "sim_time": f"{outcome.sim_time:.6f}"})
        self.writer.finish()
        write_output(self.path, self.buffer.getvalue())
