"""Every trial of a store, every field, for tools that want the raw trials rather than
the report: JSON as stored, or CSV with one column per sampled value and measurement."""

from __future__ import annotations

import json
from dataclasses import fields
from typing import Any, Sequence

from atd.campaign.formats import csv_text
from atd.campaign.record import DIMENSIONS, TrialRecord

EXPORT_FORMATS = ("csv", "json")

#: The dict fields a CSV flattens to one column per name, `sampled.dx`, `measurements.lift`.
_FLATTENED = ("sampled", "measurements")
#: Record fields that are not CSV columns under their own name (`perturbation` is `sampled`).
_NOT_COLUMNS = frozenset({"cell", "perturbation", "measurements"})


def export(records: Sequence[TrialRecord], fmt: str) -> str:
    """The trials in `fmt`, one of EXPORT_FORMATS, ending with a newline."""
    rows = [r.as_dict() for r in records]
    if fmt == "json":
        return json.dumps(rows, indent=2) + "\n"
    return csv_text(_columns(rows), [_flat(row) for row in rows])


def _columns(rows: Sequence[dict[str, Any]]) -> list[str]:
    """The cell's dimensions, the record's other fields in their order, then each
    flattened name found in any trial."""
    columns = [*DIMENSIONS, *(f.name for f in fields(TrialRecord) if f.name not in _NOT_COLUMNS)]
    for name in _FLATTENED:
        columns += sorted({f"{name}.{key}" for row in rows for key in row[name]})
    return columns


def _flat(row: dict[str, Any]) -> dict[str, Any]:
    flat = {name: value for name, value in row.items() if name not in _FLATTENED}
    flat["events"] = json.dumps(row["events"])
    for name in _FLATTENED:
        flat.update({f"{name}.{key}": value for key, value in row[name].items()})
    return flat
