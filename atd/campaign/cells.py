"""From a spec to the trials it asks for: every cell (one value of each dimension), each
with its trials, each trial with a seed that depends only on (base seed, cell, index), so
a result never depends on the number of workers, their order or the machine."""

from __future__ import annotations

import hashlib
import itertools
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from atd.campaign.record import DIMENSIONS, Cell
from atd.campaign.spec import LoadedSpec, Perturbation, TaskEntry
from factories.registry import factory_class


@dataclass(frozen=True)
class TrialPlan:
    """Everything a worker needs to run one trial, and nothing it must look up elsewhere."""

    cell: Cell
    index: int
    seed: int
    task_file: str  # absolute path of the ATD
    judge: str | None  # "lift", "place", or None: chosen from the task's states
    perturbation: Perturbation
    budget: float  # simulated seconds before the watchdog
    record_failed: str | None = None  # a folder: a trial the judge fails is recorded there (MCAP)

    @property
    def recording_name(self) -> str:
        return f"{self.cell.key.replace('/', '__')}__{self.index}.mcap"


def trial_seed(base_seed: int, cell: Cell, index: int) -> int:
    """A 32-bit seed from (base seed, cell, index) alone."""
    digest = hashlib.sha256(cell.key.encode()).digest()
    words = [int.from_bytes(digest[i:i + 4], "little") for i in range(0, 16, 4)]
    return int(np.random.SeedSequence([base_seed, *words, index]).generate_state(1)[0])


def cells(loaded: LoadedSpec) -> list[tuple[Cell, TaskEntry]]:
    """Every cell of the spec, in a stable order, with the task entry it runs."""
    spec = loaded.spec
    robots = []
    for entry in spec.robot_entries:
        arms = entry.arms or (factory_class(entry.name).arms[0].name,)
        robots += [(entry.name, arm) for arm in arms]
    found = []
    for task, (robot, arm), engine, grasp, obj, perturbation in itertools.product(
            spec.task_entries, robots, spec.engines, spec.grasps, spec.objects, spec.perturbations):
        name = loaded.task_path(task).stem
        found.append((Cell(name, robot, arm, engine, grasp, obj, perturbation), task))
    return found


def parse_only(items: tuple[str, ...]) -> dict[str, set[str]]:
    """`--only DIMENSION=VALUE` options as {dimension: values}; ValueError says what is wrong."""
    only: dict[str, set[str]] = {}
    for item in items:
        dimension, sep, value = item.partition("=")
        if not sep or not value:
            raise ValueError(f"--only {item!r}: give DIMENSION=VALUE, e.g. --only robot=melfa")
        if dimension not in DIMENSIONS:
            raise ValueError(f"--only {item!r}: no dimension '{dimension}'; dimensions: {', '.join(DIMENSIONS)}")
        only.setdefault(dimension, set()).add(value)
    return only


def plans(loaded: LoadedSpec, only: dict[str, set[str]] | None = None, trials: int | None = None,
          record_failed: Path | None = None) -> list[TrialPlan]:
    """The trials of the spec's cells, narrowed to `only` and to the first `trials` of each;
    with `record_failed`, each trial the judge fails is recorded into that folder."""
    spec = loaded.spec
    count = spec.trials if trials is None else trials
    chosen = []
    for cell, task in cells(loaded):
        if only and any(getattr(cell, d) not in values for d, values in only.items()):
            continue
        for index in range(count):
            chosen.append(TrialPlan(cell, index, trial_seed(spec.base_seed, cell, index), str(loaded.task_path(task)),
                                    task.judge, spec.perturbations[cell.perturbation], spec.budget,
                                    str(record_failed) if record_failed else None))
    return chosen
