"""A campaign's results as a picture: success rate per group with its Wilson interval, and,
when the approach was perturbed, success against the size of the error for each grasp
mode, the plot that shows whether the robust grasp degrades more gracefully; for an
unscrew campaign, its rates beside thesis Tables 3.4 and 3.5.

Drawn on a bare matplotlib Figure (Agg canvas): no display, no pyplot global state.
"""

from __future__ import annotations

import io
from dataclasses import dataclass, replace
from itertools import pairwise
from typing import Sequence

import matplotlib
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from atd.campaign.record import DIMENSIONS, TrialRecord
from atd.campaign.report import Group, UnscrewRow, emptied_a_box, group, unscrew_tables

#: The approach error's magnitudes, as the perturbation records them: (key, axis label, scale to the axis unit).
APPROACH_MEASURES = (("translation", "approach translation error (cm)", 100.0),
                     ("rotation", "approach rotation error (deg)", 1.0))

_COLOURS = {"naive": "tab:blue", "robust": "tab:red"}


@dataclass(frozen=True)
class ErrorBin:
    """Trials whose approach error falls in (low, high], per grasp mode; low = high = 0 is
    the bin of trials the approach error left alone."""

    low: float
    high: float
    groups: list[Group]  # grouped by grasp


def approach_bins(records: Sequence[TrialRecord], measure: str, count: int = 5) -> list[ErrorBin]:
    """The zero bin, then `count` equal bins up to the largest `measure` sampled."""
    magnitudes = [r.perturbation.get(measure, 0.0) for r in records]
    top = max(magnitudes, default=0.0)
    ranges = [(0.0, 0.0)] + (list(pairwise(top * i / count for i in range(count + 1))) if top > 0 else [])
    bins = []
    for low, high in ranges:
        members = [r for r, m in zip(records, magnitudes) if (m == 0 if high == 0 else low < m <= high)]
        if members:
            bins.append(ErrorBin(low, high, group(members, ("grasp",))))
    return bins


def attempts_by_remaining(records: Sequence[TrialRecord]) -> dict[str, dict[int, float]]:
    """Per task, the mean grasp attempts made with k objects in the box, over its trials
    (thesis Fig. 3.27), from the box judge's `attempts_with_k_left`."""
    found: dict[str, dict[int, float]] = {}
    for task in sorted({r.cell.task for r in records}):
        trials = [r for r in records if r.cell.task == task and r.status == "ok" and emptied_a_box(r)]
        counts = {int(key.split("_")[2]) for r in trials for key in r.measurements if key.startswith("attempts_with_")}
        if trials and counts:
            found[task] = {k: sum(r.measurements.get(f"attempts_with_{k}_left", 0.0) for r in trials) / len(trials)
                           for k in sorted(counts, reverse=True)}
    return found


def draw_report(records: Sequence[TrialRecord], groups: Sequence[Group], fmt: str) -> bytes:
    """The picture, as PNG or SVG bytes (`fmt` "png" or "svg")."""
    perturbed = any(measure in r.perturbation for r in records for measure, _, _ in APPROACH_MEASURES)
    boxes = attempts_by_remaining(records)
    unscrews = [r for r in unscrew_tables(records) if r.ours.n]
    panels = 1 + perturbed * len(APPROACH_MEASURES) + bool(boxes) + bool(unscrews)
    rows = max(len(groups), 2 * len(unscrews))
    figure = Figure(figsize=(6.5 * panels, max(3.5, 0.9 + 0.28 * rows)), layout="constrained")
    axes = figure.subplots(1, panels, squeeze=False)[0]
    _rates(axes[0], groups)
    if boxes:
        _attempts(axes[-1], boxes)
    if unscrews:
        _beside_tables_3_4_3_5(axes[-1], unscrews)
    if perturbed:
        for ax, (measure, label, scale) in zip(axes[1:], APPROACH_MEASURES):
            _against_error(ax, approach_bins(records, measure), label, scale)
    out = io.BytesIO()
    with matplotlib.rc_context({"svg.hashsalt": "atd", "svg.fonttype": "none"}):
        figure.savefig(out, format=fmt, metadata={"Date": None} if fmt == "svg" else None)
    return out.getvalue()


def _label(g: Group, varying: Sequence[str]) -> str:
    return " / ".join(g.value(d) for d in varying) or "all trials"


def _percent(g: Group) -> float:
    """The success rate in percent of a group that has trials (the only ones drawn)."""
    return 100 * g.successes / g.n


def _errors(groups: Sequence[Group]) -> list[list[float]]:
    """Percent distances from each rate down to its interval's low and up to its high (at
    0/n and n/n the Wilson bound sits on the rate, a rounding error either side of it)."""
    return [[max(0.0, _percent(g) - 100 * g.interval[0]) for g in groups],
            [max(0.0, 100 * g.interval[1] - _percent(g)) for g in groups]]


def _rates(ax: Axes, groups: Sequence[Group]) -> None:
    measured = [g for g in groups if g.n]
    varying = [d for d in DIMENSIONS if len({g.value(d) for g in measured}) > 1]
    for grasp in sorted({g.value("grasp") for g in measured}):
        rows = [(y, g) for y, g in enumerate(measured) if g.value("grasp") == grasp]
        ax.errorbar([_percent(g) for _, g in rows], [y for y, _ in rows], xerr=_errors([g for _, g in rows]),
                    fmt="o", capsize=3, color=_COLOURS.get(grasp, "tab:gray"), label=grasp)
    ax.set_yticks(range(len(measured)), [f"{_label(g, varying)} (n={g.n})" for g in measured])
    ax.invert_yaxis()
    ax.set_xlim(-2, 102)
    ax.set_xlabel("success rate (%), judged by the object; bars: 95% Wilson interval")
    ax.grid(axis="x", alpha=0.3)
    if measured:
        ax.legend(title="grasp")


def _attempts(ax: Axes, by_task: dict[str, dict[int, float]]) -> None:
    for task, means in by_task.items():
        ax.plot(list(means), list(means.values()), marker="o", label=task.rsplit("_", 1)[-1])
    ax.invert_xaxis()
    ax.set_xlabel("objects in the box")
    ax.set_ylabel("grasp attempts (mean per trial)")
    ax.set_title("attempts against objects remaining (thesis Fig. 3.27)")
    ax.grid(alpha=0.3)
    ax.legend(title="method")


def _beside_tables_3_4_3_5(ax: Axes, rows: Sequence[UnscrewRow]) -> None:
    """Per condition, our success and cap-unscrewed rates (95% Wilson bars) beside the thesis's
    figure for its table and alignment (crosses)."""
    labels = []
    for y, row in enumerate(rows):
        g, thesis = row.ours, row.thesis
        unscrewed = replace(g, successes=row.unscrewed)
        for k, (ours, mark, colour, name) in enumerate(((g, "o", "tab:red", "success"),
                                                        (unscrewed, "s", "tab:blue", "cap unscrewed"))):
            at = 2 * y + k
            ax.errorbar([_percent(ours)], [at], xerr=_errors([ours]), fmt=mark, capsize=3, color=colour,
                        label=f"ours: {name}" if y == 0 else None)
            if thesis is not None:
                rate = thesis.success_rate if k == 0 else thesis.unscrewed_rate
                ax.plot([100 * rate], [at], "x", color=colour, markersize=9,
                        label=f"thesis: {name}" if y == 0 else None)
        labels += [f"{g.value('robot')}/{g.value('arm')} {g.value('engine')} T{row.table} reactive {row.alignment} "
                   f"(n={g.n})", ""]
    ax.set_yticks(range(len(labels)), labels)
    ax.invert_yaxis()
    ax.set_xlim(-2, 102)
    ax.set_xlabel("rate (%); bars: 95% Wilson interval; x: the thesis")
    ax.set_title("unscrew, cap on the table: thesis Tables 3.4, 3.5", fontsize="medium")
    ax.grid(axis="x", alpha=0.3)
    ax.legend(fontsize="small", loc="center left", bbox_to_anchor=(1.01, 0.5))


def _against_error(ax: Axes, bins: Sequence[ErrorBin], label: str, scale: float) -> None:
    grasps = sorted({g.value("grasp") for b in bins for g in b.groups})
    step = scale * max(b.high for b in bins) / 100  # lines side by side, so their bars do not hide each other
    for i, grasp in enumerate(grasps):
        points = [(scale * (b.low + b.high) / 2 + step * (i - (len(grasps) - 1) / 2), g)
                  for b in bins for g in b.groups if g.value("grasp") == grasp and g.n]
        if not points:
            continue
        ax.errorbar([x for x, _ in points], [_percent(g) for _, g in points], yerr=_errors([g for _, g in points]),
                    marker="o", capsize=3, label=grasp, color=_COLOURS.get(grasp, "tab:gray"))
    ax.set_ylim(-2, 102)
    ax.set_xlabel(f"{label}, binned; 0: none added")
    ax.set_ylabel("success rate (%)")
    ax.grid(alpha=0.3)
    ax.legend(title="grasp")
