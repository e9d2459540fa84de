"""From a spec to the trials it asks for: every cell (one value of each dimension), each
with its trials, each trial with a seed that depends only on (base seed, cell, index), so
a result never depends on the number of workers, their order or the machine."""

from __future__ import annotations

import hashlib
import itertools
from collections import Counter
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Callable, Collection, Iterator

import numpy as np

from atd.campaign.perturbation import PerturbationModel
from atd.campaign.record import DIMENSIONS, Cell
from atd.campaign.spec import LoadedSpec, TaskEntry, WorldDraw
from atd.model.files import output_problem
from factories.registry import factory_class

#: Wall-clock seconds per simulated second of budget before a trial's run is ended: far
#: slower than any engine runs here (PyBullet's slowest run is about 3x real time).
WALL_FACTOR = 4.0
WALL_FLOOR = 120.0  # s


@dataclass(frozen=True)
class TrialPlan:
    """Everything a worker needs to run one trial, and nothing it must look up elsewhere."""

    cell: Cell
    index: int
    seed: int
    task_file: str  # absolute path of the ATD
    judge: str | None  # "lift", "place", "box", "cap", or None: chosen from the task's states
    perturbation: PerturbationModel
    budget: float  # simulated seconds before the watchdog
    recording: str | None = None  # where to record the trial (MCAP) if the judge fails it
    world: WorldDraw | None = None  # the world drawn for the trial, if the spec draws one
    fixture: bool = False  # a screw-capped object stands in a clamp on the table

    @property
    def wall_limit(self) -> float:
        """Wall-clock seconds the trial's run may take before its watchdog ends it as an
        error trial: its result would then say how fast this machine is, not what happened."""
        return max(WALL_FLOOR, WALL_FACTOR * self.budget)


def recording_name(campaign: str, cell: Cell, index: int) -> str:
    """The file a failed trial is recorded to: named by its campaign (`atd campaign run` gives
    the spec's name and the store's id), so two campaigns never write the same file."""
    return f"{campaign}__{cell.key.replace('/', '__')}__{index}.mcap"


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
        tried_on = spec.perturbations[perturbation].objects
        if tried_on and obj not in tried_on:
            continue
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


#: A trial's cost relative to a MuJoCo trial of the naive grasp without error, by the values
#: of its cell that lengthen it; any other value counts 1. Wall-clock time per trial measured
#: here (`atd campaign run`, 2 trials per cell, Melfa and Baxter lifting the mug): PyBullet
#: 2.1-3.2x MuJoCo; the robust grasp 0.7-1.4x the naive one; an approach error 0.85-1.5x
#: none with the robust grasp (1.4x over 80 Tombatossals trials), but about 0.5x with a naive
#: grasp that then fails at once. The engine is the clear factor; the others only order cells
#: of one engine.
#: The perturbation is weighed by its model, whatever the spec names it.
COST = {"engine": {"pybullet": 3.0}, "grasp": {"robust": 1.1}, "perturbation": {"approach": 1.2}}


@dataclass(frozen=True)
class Plans:
    """The trials of some cells, numbered from 0 to `count` - 1 in each. Each plan is made
    when it is taken, so a spec of millions of trials costs nothing before its first runs."""

    loaded: LoadedSpec
    cells: tuple[tuple[Cell, TaskEntry], ...]
    trials: int | None = None  # trials per cell (`--trials`), for every cell; None: as the spec says
    recordings: Path | None = None  # a folder: each trial the judge fails is recorded there
    campaign: str = ""  # what the recordings' names start with (`recording_name`)

    def count(self, cell: Cell) -> int:
        """The cell's trials: `--trials` where given, else its perturbation's own number or the spec's."""
        if self.trials is not None:
            return self.trials
        spec = self.loaded.spec
        return spec.perturbations[cell.perturbation].trials or spec.trials

    def __len__(self) -> int:
        return sum(self.count(cell) for cell, _ in self.cells)

    def __iter__(self) -> Iterator[TrialPlan]:
        return self.skipping(lambda cell: ())

    def longest_first(self) -> Plans:
        """The same trials, the cells that cost most (`COST`) first, cells of equal cost in the
        spec's order: handed out so, a campaign's last trials are its shortest, and no core
        waits long for another at the end. Seeds depend on cell and index only, so the records
        are those of any other order."""
        models = {name: p.model for name, p in self.loaded.spec.perturbations.items()}

        def cost(entry: tuple[Cell, TaskEntry]) -> float:
            cell = entry[0]
            return (COST["engine"].get(cell.engine, 1.0) * COST["grasp"].get(cell.grasp, 1.0)
                    * COST["perturbation"].get(models[cell.perturbation], 1.0))

        return replace(self, cells=tuple(sorted(self.cells, key=cost, reverse=True)))

    def skipping(self, stored: Callable[[Cell], Collection[int]]) -> Iterator[TrialPlan]:
        """The plans but those whose index `stored` gives for their cell; it is asked once per
        cell, when that cell's first plan is about to be made."""
        spec = self.loaded.spec
        for cell, task in self.cells:
            task_file, done = str(self.loaded.task_path(task)), stored(cell)
            for index in range(self.count(cell)):
                if index in done:
                    continue
                recording = self.recordings / recording_name(self.campaign, cell, index) if self.recordings else None
                yield TrialPlan(cell, index, trial_seed(spec.base_seed, cell, index), task_file, task.judge,
                                spec.perturbations[cell.perturbation], spec.budget,
                                str(recording) if recording else None, spec.world, task.fixture)

    def recording_problem(self) -> str | None:
        """Why some trial's recording could not be written into `recordings` (checked before
        the first trial runs, with each cell's longest name); None when all can, or none is asked for."""
        if self.recordings is None:
            return None
        names = [recording_name(self.campaign, cell, self.count(cell) - 1) for cell, _ in self.cells]
        for name in names:
            problem = output_problem(self.recordings / name)
            if problem:
                return f"--record-failed {self.recordings / name}: {problem}"
        clash = next((n for n, k in Counter(names).items() if k > 1), None)
        return f"--record-failed: two cells would be recorded as {clash}; rename a task" if clash else None


def plans(loaded: LoadedSpec, only: dict[str, set[str]] | None = None, trials: int | None = None) -> Plans:
    """The trials of the spec's cells, narrowed to `only` and to the first `trials` of each."""
    chosen = tuple((cell, task) for cell, task in cells(loaded)
                   if not only or all(getattr(cell, d) in values for d, values in only.items()))
    return Plans(loaded, chosen, trials)
