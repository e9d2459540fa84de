"""What one trial leaves behind: the cell it belongs to, what was sampled, what the task
said and what the judge saw. One record is one row of the campaign store."""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import Any, Literal

#: The dimensions a campaign varies; a cell is one value of each.
DIMENSIONS = ("task", "robot", "arm", "engine", "grasp", "object", "perturbation")
TASK_OBJECT = "task"  # the object dimension's value for the ATD's own object


@dataclass(frozen=True)
class Cell:
    """One combination of the campaign's dimensions."""

    task: str  # the task's name (its ATD file stem)
    robot: str
    arm: str
    engine: str
    grasp: str  # "naive" | "robust"
    object: str  # an object library name, or "task" for the ATD's own object
    perturbation: str  # the spec's name for a perturbation model ("none", "approach", ...)

    @property
    def key(self) -> str:
        """Stable text naming the cell: seeds and the store are keyed on it."""
        return "/".join(getattr(self, d) for d in DIMENSIONS)


@dataclass
class TrialRecord:
    """One trial. `task_succeeded` is the task's own opinion (it reached a success
    state); `judged_succeeded` is the ground truth's; they disagree on a false success
    (task yes, truth no) or a false failure (task no, truth yes)."""

    cell: Cell
    index: int  # the trial's number within its cell, from 0
    seed: int  # derived from (base seed, cell, index) only
    status: Literal["ok", "error"] = "ok"  # error: the trial could not be run (crash, exception)
    error: str = ""
    perturbation: dict[str, float] = field(default_factory=dict)  # every sampled value, named
    task_succeeded: bool = False
    end_state: str | None = None
    summary: str = ""  # the run's outcome in ATD terms
    events: list[dict[str, Any]] = field(default_factory=list)  # events that fired: time, transition, event
    judged_succeeded: bool = False
    judge_reason: str = ""
    measurements: dict[str, float] = field(default_factory=dict)  # what the judge measured, named, SI units
    sim_time: float = 0.0  # s simulated
    wall_time: float = 0.0  # s the whole trial took, set-up included
    setup_time: float = 0.0  # s building and resetting the robot and scene
    #: Not part of the record, not stored: why the trial's recording (--record-failed) was not written.
    recording_error: str = field(default="", compare=False)

    @property
    def false_success(self) -> bool:
        return self.status == "ok" and self.task_succeeded and not self.judged_succeeded

    @property
    def false_failure(self) -> bool:
        return self.status == "ok" and not self.task_succeeded and self.judged_succeeded

    @property
    def agrees(self) -> bool:
        return self.task_succeeded == self.judged_succeeded

    def as_dict(self) -> dict[str, Any]:
        """Flat, JSON-ready: the cell's dimensions as top-level fields. The sampled values
        are under `sampled`, since `perturbation` is the cell's dimension there."""
        data = asdict(self)
        del data["recording_error"]
        data["sampled"] = data.pop("perturbation")
        data.update(data.pop("cell"))
        return data

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> TrialRecord:
        data = dict(data)
        cell = Cell(**{d: data.pop(d) for d in DIMENSIONS})
        return cls(cell=cell, perturbation=data.pop("sampled"), **data)
