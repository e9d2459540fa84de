"""What `atd report` and `atd compare` read from a recording's messages, checked as they are
read (atd/runtime/recording_format.py says what the recorder writes): the fields they draw,
their types, and one layout of pads and joints through the whole run.

Each message is parsed into only the fields drawn (a pad's taxels, most of a sensors
message, are skipped unparsed), and the signals are kept as arrays: an hour of a run is
then megabytes in memory, not the gigabyte its messages as dicts would be.
"""

from __future__ import annotations

import base64
import binascii
from dataclasses import dataclass, field
from typing import Annotated, Any, Generic, Literal, TypeVar

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError

from atd.model import ranges

M = TypeVar("M", bound=BaseModel)

RUN_TIME = ranges.Range(0.0, ranges.BUDGET.high, "s")  # the longest run `atd run --budget` allows


class MessageProblem(ValueError):
    """A message, record or metadata value that is not what the recorder writes; the text says what."""


class _Checked(BaseModel):
    # strict: "0.1" is no number; no NaN or infinity: orjson writes a NaN reading as null
    model_config = ConfigDict(strict=True, allow_inf_nan=False, frozen=True)


_ONE_LINE = r"^[^\x00-\x1f\x7f]*$"  # a name printed in a line of text: no line break, no control character
Reading = float | None  # null: a reading that was NaN (a sensor with nothing to say)
MOST_PIXELS = 8192  # across or down a depth picture: a Kinect's is 640 x 480
MOST = 64  # joints, DOFs or pads a robot may have: the robots here have at most 7, 8 and 4
Readings = Annotated[list[Reading], Field(max_length=MOST)]
PadName = Annotated[str, Field(max_length=200, pattern=_ONE_LINE)]  # a legend's entry


class _Xyz(_Checked):
    x: Reading
    y: Reading
    z: Reading


class _Pose(_Checked):
    position: _Xyz


class _Wrench(_Checked):
    force: _Xyz


class _Pad(_Checked):
    force: Reading


class SensorsMessage(_Checked):
    """Of /sensors: what the robot's sensors read."""

    arm_dq: Readings
    hand_q: Readings
    tcp: _Pose
    wrench: _Wrench
    pads: Annotated[dict[PadName, _Pad], Field(max_length=MOST)]


class TruthMessage(_Checked):
    """Of /truth: the simulator's ground truth, which no primitive sees."""

    object: _Pose | None


class DepthMessage(_Checked):
    """Of /camera/depth: a depth picture a state took, 32-bit floats in metres, 0 where the
    camera saw nothing (atd/runtime/recording_images.py)."""

    frame_id: PadName  # the camera
    width: int = Field(ge=1, le=MOST_PIXELS)
    height: int = Field(ge=1, le=MOST_PIXELS)
    encoding: Literal["32FC1"]
    data: str  # base64

    def depth(self, what: str) -> np.ndarray:
        """The picture, (height, width) metres; MessageProblem naming `what` when its data is
        not that many floats."""
        try:
            raw = base64.b64decode(self.data, validate=True)
        except binascii.Error:
            raise MessageProblem(f"{what} is not what `atd run --record` writes: data is not base64") from None
        if len(raw) != 4 * self.width * self.height:
            raise MessageProblem(f"{what} is not what `atd run --record` writes: {len(raw)} bytes of data for "
                                 f"{self.width} x {self.height} 4-byte pixels")
        return np.frombuffer(raw, dtype="<f4").reshape(self.height, self.width)


class TraceRecord(_Checked):
    """Of /task/trace: a state entered or left, an event fired, the end (atd/runtime/trace.py)."""

    t: float = Field(ge=RUN_TIME.low, le=RUN_TIME.high)
    type: str
    state: str = Field(pattern=_ONE_LINE)
    event: str = ""
    transition: str = ""
    conditions: tuple[dict[str, Any], ...] = ()  # immutable: a default list is copied for every record


class RunInfo(_Checked):
    """The metadata `atd.run`: which run this is (atd/runtime/session.py)."""

    format: int = 0
    robot: str = ""
    arm: str = ""
    engine: str = ""
    seed: int | None = None
    task: str = ""


def parsed(model: type[M], data: bytes, what: str) -> M:
    """`data` (JSON) as `model`; MessageProblem naming `what` and the first field wrong."""
    try:
        return model.model_validate_json(data)
    except ValidationError as exc:
        first = exc.errors(include_url=False, include_input=False)[0]
        where = ".".join(str(p) for p in first["loc"])
        others = exc.error_count() - 1
        more = f" (and {others} more problem{'s' if others > 1 else ''})" if others else ""
        raise MessageProblem(f"{what} is not what `atd run --record` writes: "
                             f"{f'{where}: ' if where else ''}{first['msg']}{more}") from None


@dataclass
class Timed(Generic[M]):
    """One topic's messages in the order read, each with its time (s)."""

    times: list[float] = field(default_factory=list)
    messages: list[M] = field(default_factory=list)

    def add(self, t: float, message: M) -> None:
        self.times.append(t)
        self.messages.append(message)

    def in_time_order(self) -> tuple[np.ndarray, list[M]]:
        """The times as an array, both sorted by time (a stable sort: equal times keep their order)."""
        order = np.argsort(np.array(self.times, float), kind="stable")
        return np.array(self.times, float)[order], [self.messages[i] for i in order]


@dataclass(frozen=True)
class Signals:
    """The signals drawn and compared, one row per /sensors message, and the object's true
    height, one per /truth message."""

    t: np.ndarray
    pad_force: dict[str, np.ndarray]  # each pad's normal force (N)
    wrist_force: np.ndarray  # (rows, 3): x, y, z in the hand's frame (N)
    hand_q: np.ndarray  # (rows, hand DOFs)
    arm_dq: np.ndarray  # (rows, arm joints), rad/s
    tcp_z: np.ndarray  # m
    truth_t: np.ndarray
    object_z: np.ndarray  # m; NaN where the run has no object


def signals(sensors: Timed[SensorsMessage], truth: Timed[TruthMessage]) -> Signals:
    """The arrays of the messages read; MessageProblem when a message's layout (its pads, the
    number of hand DOFs or arm joints) is not the first message's."""
    t, rows = sensors.in_time_order()
    first = rows[0]
    pads = list(first.pads)
    for when, row in zip(t, rows):
        if list(row.pads) != pads or len(row.hand_q) != len(first.hand_q) or len(row.arm_dq) != len(first.arm_dq):
            raise MessageProblem(
                f"its /sensors message at {when:.3f} s has {len(row.arm_dq)} arm joints, {len(row.hand_q)} hand DOFs "
                f"and the pads {', '.join(row.pads)[:200] or '(none)'}, where the first has {len(first.arm_dq)}, "
                f"{len(first.hand_q)} and {', '.join(pads)[:200] or '(none)'}: a run's robot does not change")
    forces = np.array([[row.pads[p].force for p in pads] for row in rows], float).reshape(len(rows), len(pads))
    truth_t, truth_rows = truth.in_time_order()
    return Signals(
        t=t, pad_force={p: forces[:, i] for i, p in enumerate(pads)},
        wrist_force=np.array([(r.wrench.force.x, r.wrench.force.y, r.wrench.force.z) for r in rows], float),
        hand_q=np.array([r.hand_q for r in rows], float).reshape(len(rows), len(first.hand_q)),
        arm_dq=np.array([r.arm_dq for r in rows], float).reshape(len(rows), len(first.arm_dq)),
        tcp_z=np.array([r.tcp.position.z for r in rows], float),
        truth_t=truth_t,
        object_z=np.array([np.nan if r.object is None else r.object.position.z for r in truth_rows], float))


# What Foxglove's 3D panel draws, and the report's key frames with it (atd/runtime/recording_scene.py).
class _Vector(_Checked):
    x: float
    y: float
    z: float


class _Quaternion(_Checked):
    x: float
    y: float
    z: float
    w: float


class ScenePose(_Checked):
    position: _Vector
    orientation: _Quaternion


class _Colour(_Checked):
    r: float = Field(ge=0, le=1)
    g: float = Field(ge=0, le=1)
    b: float = Field(ge=0, le=1)
    a: float = Field(ge=0, le=1)


class Sized(_Checked):
    """A cube, a sphere or a cylinder: its full size along x, y and z."""

    pose: ScenePose
    size: _Vector
    color: _Colour


class Model(_Checked):
    """A mesh carried in the message (STL or OBJ, base64)."""

    pose: ScenePose
    scale: _Vector
    color: _Colour
    media_type: Literal["model/stl", "model/obj"]
    data: str


Shapes = Annotated[list[Sized], Field(max_length=1000)]


class Entity(_Checked):
    """A body of the scene: its shapes, each posed in the frame it moves with."""

    frame_id: PadName
    cubes: Shapes = []
    spheres: Shapes = []
    cylinders: Shapes = []
    models: Annotated[list[Model], Field(max_length=1000)] = []


class SceneMessage(_Checked):
    """Of /truth/scene: the bodies of the run."""

    entities: Annotated[list[Entity], Field(max_length=10_000)]


class Transform(_Checked):
    parent_frame_id: PadName
    child_frame_id: PadName
    translation: _Vector
    rotation: _Quaternion


class TransformsMessage(_Checked):
    """Of /truth/tf: where each frame is in its parent, at one time."""

    transforms: Annotated[list[Transform], Field(max_length=10_000)]
