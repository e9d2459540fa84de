"""A campaign report as text: aligned for a terminal, Markdown for a README, JSON and CSV
for tools. The CSV's first columns are fixed so that scripts can rely on them."""

from __future__ import annotations

import csv
import io
import json
from typing import Any, Sequence

from atd.campaign.report import ANY, CONDITION, THESIS_ATTEMPTS, Group, Report
from atd.campaign.record import DIMENSIONS

FORMATS = ("table", "markdown", "json", "csv")

#: The report CSV's columns; any further ones come after these.
CSV_COLUMNS = (*DIMENSIONS, "n", "successes", "rate", "low", "high", "false_successes")

_COUNTS = ("n", "successes", "rate", "95% interval", "false successes", "false failures", "errors")
_THESIS_CONDITION = ("task", "robot", "arm", "engine")


def render(report: Report, fmt: str) -> str:
    """The report in `fmt`, one of FORMATS, ending with a newline."""
    if fmt == "json":
        return json.dumps(_as_json(report), indent=2) + "\n"
    if fmt == "csv":
        return csv_text([*CSV_COLUMNS, "false_failures", "errors"], [g.as_dict() for g in report.groups])
    if not report.trials:
        return "no trials stored yet\n"
    draw = _markdown if fmt == "markdown" else _aligned
    errors = sum(g.errors for g in report.groups)
    parts = [f"{report.trials} trials ({errors} could not be run), grouped by {', '.join(report.by)}; "
             "success is the judge's verdict on the object, not the task's; intervals are 95% Wilson",
             draw(*_group_table(report.groups, report.by))]
    if report.by != CONDITION:
        parts += ["per condition, all objects pooled:", draw(*_group_table(report.conditions, CONDITION))]
    if report.thesis:
        parts += [f"thesis Table 3.3 ({THESIS_ATTEMPTS} attempts per row) beside ours:", draw(*_thesis_table(report))]
    if report.boxes:
        parts += ["thesis Table 3.6 (five objects; attempts and time are means, time simulated) beside ours:",
                  draw(*_box_table(report))]
    if report.unscrews:
        parts += ["thesis Tables 3.4 (eight objects, 80 runs per row) and 3.5 (one object, cap approach off by up to "
                  "1.5 cm, 15 runs) beside ours; reactive: the unscrew's alignment (grasp naive: no, robust: yes); "
                  "success: the task said so and the cap rests on the table; unscrewed: the cap off its thread, "
                  "whatever the task said; time: the unscrew's, simulated; moves: twists",
                  draw(*_unscrew_table(report))]
        refused = [r for r in report.unscrews if r.refused]
        if refused:
            parts.append("refused:\n" + "\n".join(
                f"  {' / '.join(r.ours.value(d) for d in _THESIS_CONDITION)} / {r.ours.value('grasp')}: {r.refused}"
                for r in refused))
    return "\n\n".join(parts) + "\n"


def csv_text(columns: Sequence[str], rows: Sequence[dict[str, Any]]) -> str:
    """CSV with a header; None reads as an empty field, a missing key too."""
    out = io.StringIO()
    writer = csv.DictWriter(out, fieldnames=list(columns), lineterminator="\n", restval="")
    writer.writeheader()
    writer.writerows(rows)
    return out.getvalue()


def _percent(value: float | None) -> str:
    return "-" if value is None else f"{100 * value:.1f}%"


def _interval(low: float, high: float) -> str:
    return f"[{_percent(low)}, {_percent(high)}]"


def _counts(g: Group) -> list[str]:
    return [str(g.n), str(g.successes), _percent(g.rate), _interval(*g.interval),
            str(g.false_successes), str(g.false_failures), str(g.errors)]


def _group_table(groups: Sequence[Group], by: Sequence[str]) -> tuple[list[str], list[list[str]]]:
    header = [*by, *_COUNTS]
    return header, [[g.value(d) for d in by] + _counts(g) for g in groups]


def _thesis_table(report: Report) -> tuple[list[str], list[list[str]]]:
    header = [*_THESIS_CONDITION, "row", "thesis", "thesis 95%", "ours", "ours 95%", "n", "false successes"]
    rows = [[r.ours.value(d) for d in _THESIS_CONDITION]
            + [r.label, _percent(r.thesis_rate), _interval(*r.thesis_interval), _percent(r.ours.rate),
               _interval(*r.ours.interval), str(r.ours.n), str(r.ours.false_successes)]
            for r in report.thesis]
    return header, rows


def _box_table(report: Report) -> tuple[list[str], list[list[str]]]:
    header = [*_THESIS_CONDITION, "method", "attempts thesis", "ours", "time thesis", "ours", "success thesis",
              "ours", "ours 95%", "n", "false empties"]
    rows = []
    for r in report.boxes:
        attempts, time, rate = (f"{r.thesis[0]:.1f}", f"{r.thesis[1]:.0f} s", _percent(r.thesis[2])) if r.thesis \
            else ("-", "-", "-")
        rows.append([r.ours.value(d) for d in _THESIS_CONDITION]
                    + [r.method, attempts, f"{r.attempts:.1f}", time, f"{r.time:.0f} s", rate, _percent(r.ours.rate),
                       _interval(*r.ours.interval), str(r.ours.n), str(r.ours.false_successes)])
    return header, rows


def _unscrew_table(report: Report) -> tuple[list[str], list[list[str]]]:
    header = [*_THESIS_CONDITION, "table", "reactive", "success thesis", "ours", "ours 95%", "unscrewed thesis",
              "ours", "time thesis", "ours", "moves thesis", "ours", "n", "false successes", "errors"]
    rows = []
    for r in report.unscrews:
        g, thesis = r.ours, r.thesis
        success, unscrewed, time, moves = (
            (f"{thesis.successes}/{thesis.n} ({_percent(thesis.success_rate)})",
             f"{thesis.unscrewed}/{thesis.n} ({_percent(thesis.unscrewed_rate)})",
             f"{thesis.time:.1f} s", f"{thesis.moves:.2f}") if thesis else ("-",) * 4)
        rows.append([g.value(d) for d in _THESIS_CONDITION]
                    + [r.table, r.alignment, success, f"{g.successes}/{g.n} ({_percent(g.rate)})",
                       _interval(*g.interval), unscrewed, f"{r.unscrewed}/{g.n} ({_percent(r.unscrewed / g.n if g.n else None)})",
                       time, "-" if r.time is None else f"{r.time:.1f} s",
                       moves, "-" if r.moves is None else f"{r.moves:.2f} (of {r.counted})",
                       str(g.n), str(g.false_successes), str(g.errors)])
    return header, rows


def _numeric(text: str) -> bool:
    return text[:1].isdigit() or text[:1] in "[-"


def _aligned(header: list[str], rows: list[list[str]]) -> str:
    """Columns padded to their widest cell; numbers to the right, names to the left."""
    widths = [max(len(r[i]) for r in [header, *rows]) for i in range(len(header))]
    right = [bool(rows) and all(_numeric(r[i]) for r in rows) for i in range(len(header))]
    lines = ["  ".join(c.rjust(w) if r else c.ljust(w) for c, w, r in zip(row, widths, right)).rstrip()
             for row in [header, *rows]]
    return "\n".join(lines)


def _markdown(header: list[str], rows: list[list[str]]) -> str:
    lines = [header, ["---"] * len(header), *rows]
    return "\n".join("| " + " | ".join(row) + " |" for row in lines)


def _as_json(report: Report) -> dict[str, Any]:
    return {
        "trials": report.trials,
        "by": list(report.by),
        "any": ANY,
        "groups": [g.as_dict() for g in report.groups],
        "conditions": [g.as_dict() for g in report.conditions],
        "table_3_3": [
            {**{d: r.ours.value(d) for d in _THESIS_CONDITION}, "row": r.label,
             "thesis": {"successes": r.thesis_successes, "n": THESIS_ATTEMPTS, "rate": r.thesis_rate,
                        "low": r.thesis_interval[0], "high": r.thesis_interval[1]},
             "ours": r.ours.as_dict()}
            for r in report.thesis
        ],
        "table_3_6": [
            {**{d: r.ours.value(d) for d in _THESIS_CONDITION}, "method": r.method,
             "thesis": dict(zip(("attempts", "time", "rate"), r.thesis)) if r.thesis else None,
             "ours": {"attempts": r.attempts, "time": r.time, **r.ours.as_dict()}}
            for r in report.boxes
        ],
        "tables_3_4_3_5": [
            {**{d: r.ours.value(d) for d in _THESIS_CONDITION}, "table": r.table, "reactive": r.alignment,
             "thesis": vars(r.thesis) if r.thesis else None,
             "ours": {"unscrewed": r.unscrewed, "time": r.time, "moves": r.moves, "moves_counted": r.counted,
                      "refused": r.refused or None, **r.ours.as_dict()}}
            for r in report.unscrews
        ],
    }
