"""`atd compare`: two runs of one task side by side, state by state (two seeds, two
engines, a simulated run and a recorded real one): per state, how long each stayed and
how each signal's mean differs, as thesis 5.5-5.6 compares simulated and real runs."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from atd.review.load import Recording


@dataclass(frozen=True)
class Signal:
    name: str
    topic: str
    extract: object  # (Recording) -> array, one value per message of `topic`


def _pad_force(r: Recording) -> np.ndarray:
    rows = [sum(p["force"] for p in m["pads"].values()) / max(len(m["pads"]), 1) for _, m in r.messages["/sensors"]]
    return np.array(rows, float)


def _wrist_force(r: Recording) -> np.ndarray:
    return np.linalg.norm(np.column_stack([r.series("/sensors", "wrench", "force", a) for a in "xyz"]), axis=1)


def _hand(r: Recording) -> np.ndarray:
    return np.array([np.mean(m["hand_q"]) for _, m in r.messages["/sensors"]], float)


SIGNALS = (
    Signal("pad force (N)", "/sensors", _pad_force),
    Signal("wrist |F| (N)", "/sensors", _wrist_force),
    Signal("hand DOFs (mean)", "/sensors", _hand),
    Signal("TCP z (m)", "/sensors", lambda r: r.series("/sensors", "tcp", "position", "z")),
    Signal("object z (m, truth)", "/truth", lambda r: r.series("/truth", "object", "position", "z")),
)


def _first_visits(r: Recording) -> dict[str, tuple[float, float]]:
    found: dict[str, tuple[float, float]] = {}
    for state, start, end in r.visits():
        found.setdefault(state, (start, r.end_time if end is None else end))
    return found


def _mean_in(r: Recording, signal: Signal, span: tuple[float, float]) -> float:
    if not r.messages.get(signal.topic):
        return float("nan")
    t = r.times(signal.topic)
    values = signal.extract(r)
    inside = (t >= span[0]) & (t < span[1]) & np.isfinite(values)
    return float(values[inside].mean()) if inside.any() else float("nan")


def compare(a: Recording, b: Recording) -> tuple[list[tuple[str, float, float]], list[tuple[str, str, float, float]]]:
    """Per state both runs entered: (state, seconds in A, seconds in B); and per state and
    signal: (state, signal, mean B - mean A, mean A)."""
    va, vb = _first_visits(a), _first_visits(b)
    states = [s for s in va if s in vb]
    durations = [(s, va[s][1] - va[s][0], vb[s][1] - vb[s][0]) for s in states]
    rows = []
    for state in states:
        for signal in SIGNALS:
            mean_a, mean_b = _mean_in(a, signal, va[state]), _mean_in(b, signal, vb[state])
            rows.append((state, signal.name, mean_b - mean_a, mean_a))
    return durations, rows


def render_text(a: Recording, b: Recording) -> str:
    durations, rows = compare(a, b)
    lines = [f"A: {a.path}  ({a.run.get('robot')}, {a.run.get('engine')}, seed {a.run.get('seed')}): "
             f"{a.outcome.get('summary', '')}",
             f"B: {b.path}  ({b.run.get('robot')}, {b.run.get('engine')}, seed {b.run.get('seed')}): "
             f"{b.outcome.get('summary', '')}", ""]
    only = sorted(set(s for s, _, _ in a.visits()) ^ set(s for s, _, _ in b.visits()))
    if only:
        lines += [f"states entered by one run only: {', '.join(only)}", ""]
    names = [s.name for s in SIGNALS]
    width = max([len(s) for s, _, _ in durations] + [5])
    lines.append(f"{'state':<{width}}  {'time A':>7} {'time B':>7}  " + "  ".join(f"{n:>20}" for n in names))
    for state, time_a, time_b in durations:
        cells = []
        for name in names:
            diff, mean_a = next((d, m) for s, g, d, m in rows if s == state and g == name)
            cells.append(f"{'' if np.isnan(diff) else f'{diff:+.4g} (A {mean_a:.4g})':>20}")
        lines.append(f"{state:<{width}}  {time_a:7.3f} {time_b:7.3f}  " + "  ".join(cells))
    lines.append("")
    lines.append("each signal: mean in B minus mean in A over the state's first visit (A's own mean in brackets)")
    return "\n".join(lines)
