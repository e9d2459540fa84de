"""A recording read back: the signals drawn, the trace of the task, the run's metadata,
and the ESTD that ran; or, for anything else, one line saying what is wrong with it.

The work is bounded by the file's size (atd/review/mcap_records.py), and what is kept by
what is drawn (atd/review/messages.py).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

import numpy as np
from mcap.records import Attachment, Channel, Message, Metadata, Schema

from atd.model.estd import Estd
from atd.model.estd_xml import parse_estd
from atd.model.files import InputError, read_capped
from atd.review.mcap_records import Damaged, records
from atd.review.messages import (RUN_TIME, DepthMessage, MessageProblem, RunInfo, SensorsMessage, Signals, Timed,
                                 TraceRecord, TruthMessage, parsed, signals)
from atd.runtime.recording_format import CLOCK, RECORDING_FORMAT

RECORDING_CAP = 2 << 30  # bytes: hours of a run at 100 Hz
ESTD_ATTACHMENT = "task.estd.xml"
TIME_SLACK = 1e-3  # s: the outcome's time is written to the microsecond, a message's to the nanosecond
_READ = {"/sensors": SensorsMessage, "/truth": TruthMessage, "/task/trace": TraceRecord,
         "/camera/depth": DepthMessage}  # the rest is skipped
_REQUIRED = ("/sensors", "/task/trace")  # /truth is not: a real robot's recording has none


class RecordingError(Exception):
    """Not a recording `atd` can read; the message says why, in one line."""


@dataclass(frozen=True)
class Picture:
    """A depth picture a state took: when, with which camera, and the depths (m, 0 where
    nothing was seen)."""

    t: float
    camera: str
    depth: np.ndarray  # (height, width)


@dataclass(frozen=True)
class Recording:
    path: Path
    run: RunInfo
    outcome: dict[str, str]  # succeeded, summary, end_state, sim_time
    end_time: float  # s: the outcome's, or the last message's when the recording has none
    estd: Estd | None
    estd_problem: str  # why the attached ESTD could not be read; "" when it could, or there is none
    trace: list[TraceRecord]
    signals: Signals
    pictures: list[Picture]  # the depth camera's, in time order (a run that took none: none)
    arm_joints: tuple[str, ...]  # a name per column of signals.arm_dq
    hand_dofs: tuple[str, ...]  # a name per column of signals.hand_q
    zero: int  # ns: the log time of simulated 0 (the wall clock when the run started)

    @cached_property
    def visits(self) -> list[tuple[str, float, float | None]]:
        """Each stay in a state: (path, entered, left or None while the run ended in it)."""
        stays: list[tuple[str, float, float | None]] = []
        open_: dict[str, int] = {}
        for record in self.trace:
            if record.type == "enter":
                open_[record.state] = len(stays)
                stays.append((record.state, record.t, None))
            elif record.type == "exit" and record.state in open_:
                i = open_.pop(record.state)
                stays[i] = (stays[i][0], stays[i][1], record.t)
        return stays

    def events(self) -> list[TraceRecord]:
        return [r for r in self.trace if r.type == "event"]


def load(path: Path) -> Recording:
    """Read a recording; RecordingError, naming the file and what is wrong, when it is not one."""
    try:
        data = read_capped(path, RECORDING_CAP)
    except InputError as exc:
        raise RecordingError(f"{path}: {exc}") from None
    if not data:
        raise RecordingError(f"{path}: the file is empty; make a recording with atd run --record")
    try:
        return _read(path, data)
    except Damaged as exc:
        raise RecordingError(f"{path}: not an MCAP recording: {exc}; record the run with atd run --record") from None
    except MessageProblem as exc:
        raise RecordingError(f"{path}: {exc}") from None


def _read(path: Path, data: bytes) -> Recording:
    schemas: dict[int, Schema] = {}
    topics: dict[int, str | None] = {}  # channel id -> the topic read from it, None for one skipped
    meta: dict[str, dict[str, str]] = {}
    estd_xml: bytes | None = None
    timed: dict[str, Timed] = {topic: Timed() for topic in _READ}
    sensors_meta: dict[str, str] = {}
    zero: int | None = None  # ns: the log time of simulated 0, once a message has been read
    for record in records(data):
        if isinstance(record, Message):
            if record.channel_id not in topics:
                raise MessageProblem(f"a message on channel {record.channel_id}, which no channel record before it "
                                     f"declares: the file is damaged")
            topic = topics[record.channel_id]
            zero = _zero(meta) if zero is None else zero
            if record.log_time < zero:
                raise MessageProblem(f"a message logged before the run started (its {CLOCK} metadata): "
                                     f"the recording is damaged")
            if topic is not None:
                t = (record.log_time - zero) / 1e9
                timed[topic].add(t, parsed(_READ[topic], record.data, f"its {topic} message at {t:.3f} s"))
        elif isinstance(record, Schema):
            schemas[record.id] = record
        elif isinstance(record, Channel):
            topics[record.id] = _topic(record, schemas)
            if record.topic == "/sensors":
                sensors_meta = record.metadata
        elif isinstance(record, Metadata):
            if record.name == CLOCK and zero is not None:
                raise MessageProblem(f"its {CLOCK} metadata comes after its first message: the file is damaged")
            meta[record.name] = record.metadata
        elif isinstance(record, Attachment) and record.name == ESTD_ATTACHMENT:
            estd_xml = record.data
    run = _run(meta)
    for topic in _REQUIRED:
        if not timed[topic].times:
            raise MessageProblem(f"it holds no {topic} messages, which every recording of `atd run --record` has")
    outcome = meta.get("atd.outcome", {})
    end_time = _end_time(outcome, timed)
    _, trace = timed["/task/trace"].in_time_order()
    estd, estd_problem = None, ""
    if estd_xml is not None:
        estd, found = parse_estd(estd_xml, ESTD_ATTACHMENT)
        estd_problem = "" if estd is not None else found[0].render()
    times, taken = timed["/camera/depth"].in_time_order()
    pictures = [Picture(t, m.frame_id, m.depth(f"its /camera/depth message at {t:.3f} s"))
                for t, m in zip(times.tolist(), taken)]
    drawn = signals(timed["/sensors"], timed["/truth"])
    return Recording(path, run, outcome, end_time, estd, estd_problem, trace, drawn, pictures,
                     _names(sensors_meta.get("arm_joints", ""), drawn.arm_dq.shape[1], "q{}", 1),
                     _names(sensors_meta.get("hand_dofs", ""), drawn.hand_q.shape[1], "dof {}", 0), zero or 0)


def _names(recorded: str, count: int, fallback: str, first: int) -> tuple[str, ...]:
    """The names the recorder wrote in the /sensors channel's metadata (the robot's own, from
    its description), one per column; numbered ones where they are missing or do not fit."""
    names = tuple(recorded.split())
    return names if len(names) == count else tuple(fallback.format(k + first) for k in range(count))


def _topic(channel: Channel, schemas: dict[int, Schema]) -> str | None:
    """The topic of a channel read, checked to carry JSON; None for a channel skipped."""
    if channel.topic not in _READ:
        return None
    if channel.message_encoding != "json":
        raise MessageProblem(f"its {channel.topic} channel holds messages encoded as "
                             f"{channel.message_encoding[:40]!r}; `atd run --record` writes JSON")
    if channel.schema_id != 0:
        schema = schemas.get(channel.schema_id)
        if schema is None:
            raise MessageProblem(f"its {channel.topic} channel names schema {channel.schema_id}, which no schema "
                                 f"record before it declares: the file is damaged")
        if schema.encoding != "jsonschema":
            raise MessageProblem(f"its {channel.topic} channel's schema is {schema.encoding[:40]!r}, not the JSON "
                                 f"Schema ('jsonschema') that JSON messages carry")
    return channel.topic


def _zero(meta: dict[str, dict[str, str]]) -> int:
    """The log time (ns) of the run's simulated 0: the wall clock when it started, or 0 in a
    recording that says none (its log times are simulated time)."""
    value = meta.get(CLOCK, {}).get("value", "0")
    if not value.isdigit():
        raise MessageProblem(f"its {CLOCK} metadata {value[:40]!r} is not a time in ns: the recording is damaged")
    return int(value)


def _run(meta: dict[str, dict[str, str]]) -> RunInfo:
    if "atd.run" not in meta:
        raise MessageProblem("an MCAP file, but not a recording of `atd run --record` (it has no atd.run metadata)")
    if "value" not in meta["atd.run"]:
        raise MessageProblem("its atd.run metadata has no 'value': the recording is damaged")
    run = parsed(RunInfo, meta["atd.run"]["value"].encode(), "its atd.run metadata")
    if run.format != RECORDING_FORMAT:
        raise MessageProblem(f"a recording in format {run.format}, this atd reads format {RECORDING_FORMAT}; "
                             f"record the run again")
    return run


def _end_time(outcome: dict[str, str], timed: dict[str, Timed]) -> float:
    """When the run ended: the outcome's time, which no message may come after; without an
    outcome, the last message's time."""
    latest, topic = max((max(t.times), topic) for topic, t in timed.items() if t.times)
    if "sim_time" not in outcome:
        end, what = latest, f"its last message, on {topic} at {latest:.3f} s,"
    else:
        what = f"its atd.outcome metadata's sim_time {outcome['sim_time'][:40]!r}"
        try:
            end = float(outcome["sim_time"])
        except ValueError:
            raise MessageProblem(f"{what} is not a number of seconds: the recording is damaged") from None
    problem = RUN_TIME.problem(end)
    if problem:
        raise MessageProblem(f"{what} is no time a run can end at: {problem.replace('give one', 'a run ends')}")
    if latest > end + TIME_SLACK:
        raise MessageProblem(f"its {topic} message at {latest:.3f} s comes after the run's end at {end:.3f} s "
                             f"(its atd.outcome metadata's sim_time): the recording is damaged")
    return end
