"""What a campaign measured: trials grouped by the dimensions asked for, each group's
success counted by the judge (the ground truth), not by the task's own opinion, with its
95% Wilson interval; for a campaign shaped like thesis 3.4.1, Table 3.3 beside ours, and for
one that empties a box (thesis 3.4.3, the box judge), Table 3.6 beside ours, and for one
that unscrews caps (thesis 3.4.2, the cap judge), Tables 3.4 and 3.5 beside ours.
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
class ThesisUnscrew:
    """One row of thesis Tables 3.4 or 3.5, as printed there (its percentages rounded its own way)."""

    successes: int
    unscrewed: int
    n: int
    success_rate: float  # as printed
    unscrewed_rate: float  # as printed
    time: float  # s, mean time of the unscrew
    moves: float  # mean twist moves


#: Thesis 3.4.2: by (table, grasp mode): "naive" is the unscrew without its reactive alignment.
THESIS_UNSCREW: dict[tuple[str, str], ThesisUnscrew] = {
    ("3.4", "naive"): ThesisUnscrew(70, 75, 80, 0.875, 0.938, 156.47, 8.98),
    ("3.4", "robust"): ThesisUnscrew(71, 78, 80, 0.886, 0.975, 172.42, 10.06),
    ("3.5", "naive"): ThesisUnscrew(9, 10, 15, 0.60, 0.667, 57.5, 3.4),
    ("3.5", "robust"): ThesisUnscrew(12, 13, 15, 0.80, 0.867, 66.9, 3.77),
}
ALIGNMENT = {"naive": "no", "robust": "yes"}  # the grasp mode as the thesis's "reactive" column
NOISE_MEASURE = "cap_offset"  # sampled by the cap_approach model: a trial of Table 3.5


def unscrewed_a_cap(record: TrialRecord) -> bool:
    """A trial the cap judge judged (it looked at the cap)."""
    return "cap_free" in record.measurements


@dataclass(frozen=True)
class UnscrewRow:
    """One condition of an unscrew campaign (objects pooled) beside the thesis's row for the
    same table (3.5 when the cap's approach was noisy, 3.4 when nothing was perturbed) and
    alignment. `refused` is why no trial could run (a robot that cannot unscrew)."""

    ours: Group
    table: str  # "3.4", "3.5", or "-" for a perturbation the thesis did not try
    unscrewed: int  # trials whose cap came off its thread, whatever the task said
    time: float | None  # mean s of the unscrew primitive, over the trials run
    moves: float | None  # mean twist moves, over the trials whose unscrew said how many
    counted: int  # trials whose unscrew said how many
    refused: str

    @property
    def alignment(self) -> str:
        return ALIGNMENT.get(self.ours.value("grasp"), self.ours.value("grasp"))

    @property
    def thesis(self) -> ThesisUnscrew | None:
        return THESIS_UNSCREW.get((self.table, self.ours.value("grasp")))


def unscrew_tables(records: Sequence[TrialRecord]) -> list[UnscrewRow]:
    """A row per condition of every task the cap judge judged, refused conditions included."""
    tasks = {r.cell.task for r in records if r.status == "ok" and unscrewed_a_cap(r)}
    mine = [r for r in records if r.cell.task in tasks]
    sampled: dict[str, set[str]] = defaultdict(set)  # by perturbation: what its trials drew
    for r in mine:
        if r.status == "ok":
            sampled[r.cell.perturbation] |= set(r.perturbation)
    rows = []
    for g in group(mine, CONDITION):
        members = [r for r in mine if all(getattr(r.cell, d) == g.value(d) for d in CONDITION)]
        ran = [r for r in members if r.status == "ok"]
        drawn = sampled.get(g.value("perturbation"))
        table = "-" if drawn is None else "3.5" if NOISE_MEASURE in drawn else "3.4" if not drawn else "-"
        said = [r.measurements["twists"] for r in ran if "twists" in r.measurements]
        errors = [r.error for r in members if r.status == "error"]
        rows.append(UnscrewRow(
            g, table, sum(r.measurements.get("cap_free", 0.0) > 0 for r in ran),
            sum(r.measurements.get("unscrew_time", 0.0) for r in ran) / len(ran) if ran else None,
            sum(said) / len(said) if said else None, len(said),
            "" if ran else _why_refused(errors[0]) if errors else ""))
    # As the thesis: Table 3.4 before 3.5, without the alignment before with it.
    return sorted(rows, key=lambda r: (*(r.ours.value(d) for d in ("task", "robot", "arm", "engine")), r.table,
                                       r.ours.value("grasp")))


def _why_refused(error: str) -> str:
    """The translator's error line in a trial's error, without its location; else its first line."""
    lines = error.splitlines()
    found = next((line for line in lines if "error[" in line), lines[0] if lines else "")
    return found.split("]: ", 1)[-1]


@dataclass(frozen=True)
class Report:
    """Everything `atd campaign report` shows, before it is formatted."""

    by: tuple[str, ...]
    groups: list[Group]
    conditions: list[Group]  # pooled over objects
    thesis: list[ThesisRow]  # empty unless the campaign is shaped like thesis Table 3.3
    trials: int  # every stored trial, errors included
    boxes: list[BoxRow]  # empty unless the box judge judged its trials (thesis Table 3.6)
    unscrews: list[UnscrewRow]  # empty unless the cap judge judged its trials (thesis Tables 3.4, 3.5)


def build_report(records: Sequence[TrialRecord], by: Sequence[str] = DIMENSIONS) -> Report:
    conditions = group(records, CONDITION)
    boxes = table_3_6(records)
    unscrews = unscrew_tables(records)
    return Report(by=tuple(d for d in DIMENSIONS if d in by), groups=group(records, by), conditions=conditions,
                  thesis=[] if boxes or unscrews else table_3_3(conditions), trials=len(records), boxes=boxes,
                  unscrews=unscrews)
