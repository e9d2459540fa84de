"""The end-of-run summary, in the ATD's own terms: the path through the task graph, the
events that fired with the readings behind them, and the outcome; as text, or as data."""

from __future__ import annotations

from typing import Callable, TypeVar

from atd.model.estd import Estd
from atd.model.vocabulary import StateType
from atd.runtime.executor import Outcome, Visit

T = TypeVar("T")


SECTION_LINES = 40  # lines a section of the summary shows at most; the trace keeps everything


def _evidence(condition: dict) -> str:
    details = {k: v for k, v in condition.items() if k not in ("kind", "atd", "sensors")}
    text = ", ".join(f"{k}={_short(v)}" for k, v in details.items())
    return f"{condition['kind']}({text})" if text else condition["kind"]


def _short(value: object) -> str:
    if isinstance(value, float):
        return f"{value:.3g}"
    if isinstance(value, list):
        return "[" + " ".join(_short(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k} {_short(v)}" for k, v in value.items()) + "}"
    return str(value)


def ends(items: list[T], lines: int = SECTION_LINES) -> tuple[list[T], int, list[T]]:
    """A long section's first and last `lines` // 2 items and how many lie between them; a
    short section whole (then none between, none after)."""
    half = lines // 2
    if len(items) <= lines:
        return items, 0, []
    return items[:half], len(items) - 2 * half, items[-half:]


def _capped(items: list[T], render: Callable[[T], str], what: str) -> list[str]:
    """A line per item; for a long section, the first and last lines and how many were left
    out between (only the lines shown are formatted, so a long run stays cheap to report)."""
    head, left_out, tail = ends(items)
    more = [f"  ... {left_out} more {what} (run with --trace FILE to keep every one)"] if left_out else []
    return [*map(render, head), *more, *map(render, tail)]


def summary(outcome: Outcome, records: list[dict], title: str) -> str:
    width = max((len(v.path) for v in outcome.visits), default=0)

    def visit_line(visit: Visit) -> str:
        if visit.left is None:
            return f"  {visit.entered:8.3f} s  {visit.path}"
        took = f"{visit.left - visit.entered:.3f} s"
        return (f"  {visit.entered:8.3f} s  {visit.path.ljust(width)}  {took:>9}  "
                f"left on {' & '.join(visit.left_on)} ({visit.left_by})")

    lines = [title, "", "path through the task:", *_capped(outcome.visits, visit_line, "states visited")]
    events = [r for r in records if r["type"] == "event"]
    if events:
        lines += ["", "events that fired:"]
        lines += _capped(events, lambda r: f"  {r['t']:8.3f} s  {r['atd']}: "
                                           f"{'; '.join(_evidence(c) for c in r['conditions'])}", "events")
    rtf = outcome.real_time_factor
    lines += ["", f"outcome: {outcome.summary}",
              f"simulated {outcome.sim_time:.2f} s in {outcome.wall_time:.2f} s of wall-clock time "
              f"({rtf:.1f}x real time)"]
    return "\n".join(lines)


def outcome_document(outcome: Outcome, records: list[dict]) -> dict:
    """The summary as data (`atd run --format json`): every state visited and every event
    that fired, none left out, each event with the readings behind it as the trace has them."""
    return {
        "succeeded": outcome.succeeded,
        "end_state": outcome.end_state,
        "summary": outcome.summary,
        "sim_time": round(outcome.sim_time, 6),
        "wall_time": round(outcome.wall_time, 3),
        "path": [{"state": v.path, "atd": v.atd, "entered": round(v.entered, 6),
                  "left": None if v.left is None else round(v.left, 6), "left_by": v.left_by, "left_on": v.left_on}
                 for v in outcome.visits],
        "events": [{k: v for k, v in r.items() if k != "type"} for r in records if r["type"] == "event"],
    }


def grasp_attempts(estd: Estd, visits: list[Visit]) -> list[Visit]:
    """The visits of a run to a grasp state, in any (sub-)machine: thesis 3.4.3's grasp
    attempts."""
    grasps = {prefix + state.name for prefix, machine in estd.walk() for state in machine.states
              if state.type is StateType.GRASP}
    return [visit for visit in visits if visit.path in grasps]
