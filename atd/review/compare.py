"""`atd compare`: two runs of one task side by side, state by state (two seeds, two
engines, a simulated run and a recorded real one): per state, how long each stayed and
how each signal's mean differs, as thesis 5.5-5.6 compares simulated and real runs."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from atd.review.load import Recording
from atd.review.messages import Signals
from atd.runtime.report import SECTION_LINES


@dataclass(frozen=True)
class Signal:
    name: str
    extract: Callable[[Signals], tuple[np.ndarray, np.ndarray]]  # the times, and a value at each


def _pad_force(s: Signals) -> tuple[np.ndarray, np.ndarray]:
    """The mean over the hand's pads (0 for a hand without any)."""
    return s.t, np.mean(list(s.pad_force.values()), axis=0) if s.pad_force else np.zeros(len(s.t))


def _hand(s: Signals) -> tuple[np.ndarray, np.ndarray]:
    return s.t, s.hand_q.mean(axis=1) if s.hand_q.shape[1] else np.full(len(s.t), np.nan)


SIGNALS = (
    Signal("pad force (N)", _pad_force),
    Signal("wrist |F| (N)", lambda s: (s.t, np.linalg.norm(s.wrist_force, axis=1))),
    Signal("hand DOFs (mean)", _hand),
    Signal("TCP z (m)", lambda s: (s.t, s.tcp_z)),
    Signal("object z (m, truth)", lambda s: (s.truth_t, s.object_z)),
)


def _first_visits(r: Recording) -> dict[str, tuple[float, float]]:
    found: dict[str, tuple[float, float]] = {}
    for state, start, end in r.visits:
        found.setdefault(state, (start, r.end_time if end is None else end))
    return found


def _mean_in(series: tuple[np.ndarray, np.ndarray], span: tuple[float, float]) -> float:
    t, values = series
    inside = (t >= span[0]) & (t < span[1]) & np.isfinite(values)
    return float(values[inside].mean()) if inside.any() else float("nan")


def compare(a: Recording, b: Recording) -> tuple[list[tuple[str, float, float]], list[tuple[str, str, float, float]]]:
    """Per state both runs entered, in A's order: (state, seconds in A, seconds in B); and per
    state and signal: (state, signal, mean B - mean A, mean A). Both empty when the runs
    entered no state in common."""
    va, vb = _first_visits(a), _first_visits(b)
    states = [s for s in va if s in vb]
    durations = [(s, va[s][1] - va[s][0], vb[s][1] - vb[s][0]) for s in states]
    rows = []
    for signal in SIGNALS:
        series_a, series_b = signal.extract(a.signals), signal.extract(b.signals)
        for state in states:
            mean_a, mean_b = _mean_in(series_a, va[state]), _mean_in(series_b, vb[state])
            rows.append((state, signal.name, mean_b - mean_a, mean_a))
    return durations, rows


def entered(r: Recording) -> set[str]:
    return {state for state, _, _ in r.visits}


def listed(states: set[str], most: int = SECTION_LINES) -> str:
    """State names in a line, at most `most` of them."""
    names = sorted(states)
    shown = ", ".join(names[:most])
    return shown if len(names) <= most else f"{shown} and {len(names) - most} more"


def render_text(a: Recording, b: Recording, durations: list[tuple[str, float, float]],
                rows: list[tuple[str, str, float, float]]) -> str:
    """The comparison `compare` made, as a table: a line per state both runs entered."""
    lines = [f"{name}: {r.path}  ({r.run.robot}, {r.run.engine}, seed {r.run.seed}): {r.outcome.get('summary', '')}"
             for name, r in (("A", a), ("B", b))] + [""]
    only = entered(a) ^ entered(b)
    if only:
        lines += [f"states entered by one run only: {listed(only)}", ""]
    names = [s.name for s in SIGNALS]
    cell = {(state, signal): (d, m) for state, signal, d, m in rows}
    width = max([len(s) for s, _, _ in durations] + [5])
    lines.append(f"{'state':<{width}}  {'time A':>7} {'time B':>7}  " + "  ".join(f"{n:>20}" for n in names))
    for state, time_a, time_b in durations:
        cells = []
        for name in names:
            diff, mean_a = cell[state, name]
            cells.append(f"{'' if np.isnan(diff) else f'{diff:+.4g} (A {mean_a:.4g})':>20}")
        lines.append(f"{state:<{width}}  {time_a:7.3f} {time_b:7.3f}  " + "  ".join(cells))
    lines.append("")
    lines.append("each signal: mean in B minus mean in A over the state's first visit (A's own mean in brackets)")
    return "\n".join(lines)


def _number(value: float) -> float | None:
    """A mean for JSON: null where a run has no sample in the state (NaN is not JSON)."""
    return None if np.isnan(value) else round(float(value), 6)


def as_document(a: Recording, b: Recording, durations: list[tuple[str, float, float]],
                rows: list[tuple[str, str, float, float]]) -> dict:
    """The comparison `compare` made, as data (`atd compare --format json`): each run, the
    states one run entered and the other not, and per state both durations and per signal
    the mean in A and the difference B - A."""
    cell = {(state, signal): (d, m) for state, signal, d, m in rows}
    return {
        "runs": {name: {"path": str(r.path), "robot": r.run.robot, "arm": r.run.arm, "engine": r.run.engine,
                        "seed": r.run.seed, "task": r.run.task, "outcome": r.outcome}
                 for name, r in (("a", a), ("b", b))},
        "only_in_one": sorted(entered(a) ^ entered(b)),
        "states": [{"state": state, "time_a": round(time_a, 6), "time_b": round(time_b, 6),
                    "signals": {s.name: {"mean_a": _number(cell[state, s.name][1]),
                                         "difference": _number(cell[state, s.name][0])} for s in SIGNALS}}
                   for state, time_a, time_b in durations],
        "difference": "mean in B minus mean in A over the state's first visit",
    }
