"""The trace of a run: JSON lines, one per state entry, state exit, event and end.

Records carry simulated time only (never wall-clock time), so the same seed gives the
same trace, byte for byte.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

from atd.model.files import write_output


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
    """Collects records in memory; `save` writes them as JSON lines in one atomic step, so
    neither a crashed run nor a full disk leaves a half-written trace behind."""

    def __init__(self) -> None:
        self.records: list[dict[str, Any]] = []

    def write(self, kind: str, time: float, **fields: Any) -> None:
        self.records.append({"t": round(time, 6), "type": kind, **_plain(fields)})

    def save(self, path: Path) -> None:
        """Write the trace to `path`; OutputError when it cannot be written."""
        write_output(path, "".join(json.dumps(r, sort_keys=True) + "\n" for r in self.records).encode())
