"""The trace of a run: JSON lines, one per state entry, state exit, event and end.

Records carry simulated time only (never wall-clock time), so the same seed gives the
same trace, byte for byte.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import IO, Any

import numpy as np


def _plain(value: Any) -> Any:
    """JSON-ready values: arrays to lists, numbers rounded to what sensors can tell apart."""
    if isinstance(value, np.ndarray):
        return [_plain(v) for v in value.tolist()]
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (float, np.floating)):
        return round(float(value), 6)
    if isinstance(value, np.integer):
        return int(value)
    return value


class Trace:
    """Collects records in memory and, when given a path, streams them to a file.

    The file is written under a temporary name and moved into place on `close()`, so a
    crashed run never leaves a half-written trace where the complete one would be.
    """

    def __init__(self, path: Path | None = None) -> None:
        self.records: list[dict[str, Any]] = []
        self._path = Path(path) if path else None
        self._tmp = self._path.with_name(f".{self._path.name}.partial") if self._path else None
        self._out: IO[str] | None = self._tmp.open("w") if self._tmp else None

    def write(self, kind: str, time: float, **fields: Any) -> None:
        record = {"t": round(time, 6), "type": kind, **_plain(fields)}
        self.records.append(record)
        if self._out:
            self._out.write(json.dumps(record, sort_keys=True) + "\n")

    def close(self) -> None:
        if self._out and self._tmp and self._path:
            self._out.close()
            self._tmp.replace(self._path)
            self._out = None

    def discard(self) -> None:
        if self._out and self._tmp:
            self._out.close()
            self._tmp.unlink(missing_ok=True)
            self._out = None
