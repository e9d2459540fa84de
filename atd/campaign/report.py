"""What a campaign measured: trials grouped by the dimensions asked for, each group's
success counted by the judge (the ground truth), not by the task's own opinion, with its
95% Wilson interval; for a campaign shaped like thesis 3.4.1, Table 3.3 beside ours, and for
one that empties a box (thesis 3.4.3, the box judge), Table 3.6 beside ours.
"""

from __future__ import annotations

from collections import defaultdict
from dataclasses import dataclass
from typing import Any, Iterable, Sequence

from atd.campaign.record import DIMENSIONS, TrialRecord
from atd.campaign.stats import wilson

#: What a dimension not grouped on reads.
ANY = "*"

#: A condition in the thesis's sense: everything but the object, whose trials are pooled.
CONDITION = tuple(d for d in DIMENSIONS if d != "object")

#: Thesis 3.4.1, Table 3.3: stable grasps out of 100 attempts, by (grasp, perturbation).
THESIS_TABLE_3_3: dict[tuple[str, str], int] = {
    ("naive", "none"): 88,
    ("robust", "none"): 99,
    ("naive", "approach"): 19,
    ("robust", "approach"): 59,
}
THESIS_ATTEMPTS = 100
_THESIS_LABELS = {
    ("naive", "none"): "naive",
    ("robust", "none"): "robust",
    ("naive", "approach"): "naive + error",
    ("robust", "approach"): "robust + error",
}


@dataclass(frozen=True)
class Group:
    """The trials sharing one value of each grouped dimension. Error trials (the trial
    could not be run) are counted apart and are not in n."""

    key: tuple[str, ...]  # one value per DIMENSIONS entry, ANY where not grouped on
    n: int
    successes: int
    false_successes: int
    false_failures: int
    errors: int

    @property
    def rate(self) -> float | None:
        return self.successes / self.n if self.n else None

    @property
    def interval(self) -> tuple[float, float]:
        return wilson(self.successes, self.n)

    def value(self, dimension: str) -> str:
        return self.key[DIMENSIONS.index(dimension)]

    def as_dict(self) -> dict[str, Any]:
        """The CSV's columns, in its order: dimensions, counts, rate and interval."""
        low, high = self.interval
        return {**dict(zip(DIMENSIONS, self.key)), "n": self.n, "successes": self.successes,
                "rate": self.rate, "low": low, "high": high, "false_successes": self.false_successes,
                "false_failures": self.false_failures, "errors": self.errors}


def parse_by(text: str) -> tuple[str, ...]:
    """`--by task,grasp` as dimensions; ValueError naming the unknown one and the choices."""
    names = tuple(name.strip() for name in text.split(",") if name.strip())
    for name in names:
        if name not in DIMENSIONS:
            raise ValueError(f"'{name}' is not a dimension; choose from {', '.join(DIMENSIONS)}")
    if not names:
        raise ValueError(f"name at least one dimension: {', '.join(DIMENSIONS)}")
    return names


def group(records: Iterable[TrialRecord], by: Sequence[str] = DIMENSIONS) -> list[Group]:
    """One group per combination of the `by` dimensions found in `records`, sorted."""
    members: dict[tuple[str, ...], list[TrialRecord]] = defaultdict(list)
    for record in records:
        members[tuple(getattr(record.cell, d) if d in by else ANY for d in DIMENSIONS)].append(record)
    groups = []
    for key, trials in sorted(members.items()):
        ran = [t for t in trials if t.status == "ok"]
        groups.append(Group(key=key, n=len(ran), successes=sum(t.judged_succeeded for t in ran),
                            false_successes=sum(t.false_success for t in ran),
                            false_failures=sum(t.false_failure for t in ran),
                            errors=len(trials) - len(ran)))
    return groups


@dataclass(frozen=True)
class ThesisRow:
    """One condition of ours beside the thesis's figure for the same grasp and error."""

    label: str  # the thesis's row: naive, robust, naive + error, robust + error
    thesis_successes: int  # of THESIS_ATTEMPTS
    ours: Group

    @property
    def thesis_rate(self) -> float:
        return self.thesis_successes / THESIS_ATTEMPTS

    @property
    def thesis_interval(self) -> tuple[float, float]:
        return wilson(self.thesis_successes, THESIS_ATTEMPTS)


def table_3_3(conditions: Sequence[Group]) -> list[ThesisRow]:
    """Table 3.3 beside each of our conditions, when every condition is one the thesis
    measured (grasp naive or robust, perturbation none or approach); empty otherwise."""
    shapes = [(c.value("grasp"), c.value("perturbation")) for c in conditions]
    if not shapes or any(shape not in THESIS_TABLE_3_3 for shape in shapes):
        return []
    order = list(THESIS_TABLE_3_3)
    rows = [ThesisRow(_THESIS_LABELS[shape], THESIS_TABLE_3_3[shape], c) for shape, c in zip(shapes, conditions)]
    return sorted(rows, key=lambda r: (tuple(r.ours.value(d) for d in ("task", "robot", "arm", "engine")),
                                       order.index((r.ours.value("grasp"), r.ours.value("perturbation")))))


#: Thesis 3.4.3, Table 3.6: emptying a box of five objects, per approach-vector generator:
#: mean grasp attempts, mean time (s), success rate.
THESIS_TABLE_3_6: dict[str, tuple[float, float, float]] = {
    "random": (30.5, 284.0, 1.0),
    "exploration": (32.8, 335.0, 1.0),
    "vision": (7.1, 101.0, 1.0),
}


def emptied_a_box(record: TrialRecord) -> bool:
    """A trial the box judge judged (it counted what was left)."""
    return "remaining" in record.measurements


@dataclass(frozen=True)
class BoxRow:
    """One condition of a box-emptying campaign: its success, and its mean grasp attempts and
    simulated time over the trials run, beside Table 3.6's row for the task's generator (the
    last word of the task's name: empty_the_box_vision)."""

    ours: Group
    attempts: float
    time: float

    @property
    def method(self) -> str:
        return self.ours.value("task").rsplit("_", 1)[-1]

    @property
    def thesis(self) -> tuple[float, float, float] | None:
        return THESIS_TABLE_3_6.get(self.method)


def table_3_6(records: Sequence[TrialRecord]) -> list[BoxRow]:
    """A row per condition of the trials the box judge judged."""
    judged = [r for r in records if r.status == "ok" and emptied_a_box(r)]
    rows = []
    for g in group(judged, CONDITION):
        members = [r for r in judged if all(getattr(r.cell, d) == g.value(d) for d in CONDITION)]
        rows.append(BoxRow(g, sum(r.measurements["attempts"] for r in members) / len(members),
                           sum(r.sim_time for r in members) / len(members)))
    return rows


@dataclass(frozen=True)
class Report:
    """Everything `atd campaign report` shows, before it is formatted."""

    by: tuple[str, ...]
    groups: list[Group]
    conditions: list[Group]  # pooled over objects
    thesis: list[ThesisRow]  # empty unless the campaign is shaped like thesis Table 3.3
    trials: int  # every stored trial, errors included
    boxes: list[BoxRow]  # empty unless the box judge judged its trials (thesis Table 3.6)


def build_report(records: Sequence[TrialRecord], by: Sequence[str] = DIMENSIONS) -> Report:
    conditions = group(records, CONDITION)
    boxes = table_3_6(records)
    return Report(by=tuple(d for d in DIMENSIONS if d in by), groups=group(records, by), conditions=conditions,
                  thesis=[] if boxes else table_3_3(conditions), trials=len(records), boxes=boxes)
