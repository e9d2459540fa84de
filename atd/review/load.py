"""A recording read back: each topic's messages as time series, the run's metadata, and
the ESTD that ran."""

from __future__ import annotations

import io
import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from mcap.reader import make_reader

from atd.model.estd import Estd
from atd.model.estd_xml import parse_estd
from atd.model.files import InputError, read_capped
from atd.runtime.recording_format import RECORDING_FORMAT

RECORDING_CAP = 2 << 30  # bytes: hours of a run at 100 Hz


class RecordingError(Exception):
    """Not a recording `atd` can read; the message says why."""


@dataclass
class Recording:
    path: Path
    run: dict[str, Any]  # robot, arm, engine, seed, task
    outcome: dict[str, str]  # succeeded, summary, end_state, sim_time
    estd: Estd | None
    messages: dict[str, list[tuple[float, dict[str, Any]]]] = field(default_factory=dict)  # topic -> (t, message)

    @property
    def trace(self) -> list[dict[str, Any]]:
        return [m for _, m in self.messages.get("/task/trace", [])]

    def times(self, topic: str) -> np.ndarray:
        return np.array([t for t, _ in self.messages.get(topic, [])])

    def series(self, topic: str, *keys: str | int) -> np.ndarray:
        """One field of every message of `topic`, following `keys` into the message
        (e.g. "pads", "tactile_left", "force"), as an array (rows: messages)."""
        rows = []
        for _, message in self.messages.get(topic, []):
            value: Any = message
            for key in keys:
                value = value[key] if value is not None else None
            rows.append(np.nan if value is None else value)
        return np.array(rows, dtype=float)

    def visits(self) -> list[tuple[str, float, float | None]]:
        """Each stay in a state: (path, entered, left or None while the run ended in it)."""
        stays: list[tuple[str, float, float | None]] = []
        open_: dict[str, int] = {}
        for record in self.trace:
            if record["type"] == "enter":
                open_[record["state"]] = len(stays)
                stays.append((record["state"], record["t"], None))
            elif record["type"] == "exit" and record["state"] in open_:
                i = open_.pop(record["state"])
                stays[i] = (stays[i][0], stays[i][1], record["t"])
        return stays

    @property
    def end_time(self) -> float:
        return float(self.outcome.get("sim_time", 0.0))


def load(path: Path) -> Recording:
    """Read a recording whole; RecordingError when it is not one."""
    try:
        data = read_capped(path, RECORDING_CAP)
    except InputError as exc:
        raise RecordingError(f"{path}: {exc}") from None
    try:
        reader = make_reader(io.BytesIO(data))
        meta = {m.name: dict(m.metadata) for m in reader.iter_metadata()}
        attachments = {a.name: a.data for a in reader.iter_attachments()}
        messages: dict[str, list[tuple[float, dict[str, Any]]]] = {}
        for _, channel, message in reader.iter_messages(log_time_order=True):
            messages.setdefault(channel.topic, []).append((message.log_time / 1e9, json.loads(message.data)))
    except Exception as exc:  # noqa: BLE001 - bytes from anywhere through mcap, zstd, lz4, JSON: any failure says the same
        raise RecordingError(f"{path}: not an MCAP recording ({exc}); make one with atd run --record") from None
    if "atd.run" not in meta:
        raise RecordingError(f"{path}: an MCAP file, but not a recording of `atd run --record`")
    run = json.loads(meta["atd.run"]["value"])
    if run.get("format") != RECORDING_FORMAT:
        raise RecordingError(f"{path}: a recording in format {run.get('format', 0)}, this atd reads format "
                             f"{RECORDING_FORMAT}; record the run again")
    estd = None
    if "task.estd.xml" in attachments:
        estd, _ = parse_estd(attachments["task.estd.xml"], "task.estd.xml")
    return Recording(path, run, meta.get("atd.outcome", {}), estd, messages)
