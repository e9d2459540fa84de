"""The end-of-run summary, in the ATD's own terms: the path through the task graph, the
events that fired with the readings behind them, and the outcome."""

from __future__ import annotations

from atd.runtime.executor import Outcome


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


def summary(outcome: Outcome, records: list[dict], title: str) -> str:
    lines = [title, "", "path through the task:"]
    width = max((len(v.path) for v in outcome.visits), default=0)
    for visit in outcome.visits:
        if visit.left is None:
            lines.append(f"  {visit.entered:8.3f} s  {visit.path}")
            continue
        took = f"{visit.left - visit.entered:.3f} s"
        lines.append(f"  {visit.entered:8.3f} s  {visit.path.ljust(width)}  {took:>9}  "
                     f"left on {' & '.join(visit.left_on)} ({visit.left_by})")
    events = [r for r in records if r["type"] == "event"]
    if events:
        lines += ["", "events that fired:"]
        for record in events:
            why = "; ".join(_evidence(c) for c in record["conditions"])
            lines.append(f"  {record['t']:8.3f} s  {record['atd']}: {why}")
    rtf = outcome.real_time_factor
    lines += ["", f"outcome: {outcome.summary}",
              f"simulated {outcome.sim_time:.2f} s in {outcome.wall_time:.2f} s of wall-clock time "
              f"({rtf:.1f}x real time)"]
    return "\n".join(lines)
