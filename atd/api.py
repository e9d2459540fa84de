"""`atd` from Python: what `atd validate`, `translate`, `run` and `campaign` do, as functions.

Each raises `AtdError` with the same located text the command line prints, so a script sees
a bad file as the user would. docs/api.md shows them in use; a test runs its examples.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Iterator

from atd.model import Diagnostic, Task, has_errors, load_task
from atd.model.diagnostics import render_all
from atd.model.estd import Estd


class AtdError(Exception):
    """A file that cannot be used, or a robot that cannot do the task: the reasons, located."""


def validate(path: str | Path) -> list[Diagnostic]:
    """Every problem of the task file and its sub-tasks (empty when it is fine)."""
    return load_task(path)[1]


def load(path: str | Path) -> Task:
    """The task of an ATD file; AtdError when it has errors."""
    task, found = load_task(path)
    if task is None or has_errors(found):
        raise AtdError(render_all(found))
    return task


def translate(task: Task | str | Path, robot: str, arm: str | None = None, grasp: str = "robust",
              roles: dict[str, str] | None = None) -> Estd:
    """The ESTD of `task` for `robot` (its `arm`; a task with roles: `roles` binds some to arms
    by name, as `--role` does); AtdError with the reasons when it cannot do it."""
    from factories.registry import create
    from translator import translate as translated

    task = task if isinstance(task, Task) else load(task)
    try:
        result = translated(task, create(robot, arm=arm, grasp=grasp), roles=roles)
    except ValueError as exc:  # a binding naming a role or an arm that is not there
        raise AtdError(str(exc)) from None
    if result.estd is None:
        raise AtdError(render_all(result.diagnostics) + f"\n{robot} cannot do this task")
    return result.estd


@dataclass(frozen=True)
class RunResult:
    """How a run ended (the ATD's terms) and where every object came to rest (the simulator's)."""

    succeeded: bool
    summary: str
    end_state: str | None
    path: tuple[str, ...]  # the states visited, in order
    sim_time: float
    object_positions: dict[str, tuple[float, float, float]]


def run(task: Task | Estd | str | Path, robot: str | None = None, arm: str | None = None, engine: str = "mujoco",
        seed: int = 0, world: str | Path | None = None, record: str | Path | None = None,
        roles: dict[str, str] | None = None) -> RunResult:
    """Run an ATD (translated for `robot`, its `roles` bound as `translate` binds them) or an
    ESTD headless, as `atd run` does."""
    from atd.runtime.session import Run, RunError, world_scene
    from factories.registry import create

    estd = task if isinstance(task, Estd) else translate(task, _named(robot), arm, roles=roles)
    factory = create(estd.robot, arm=estd.arm)
    try:
        scene = world_scene(estd, Path(world), seed) if world is not None else None
        session = Run(estd, factory, engine=engine, seed=seed, scene=scene,
                      record=Path(record) if record is not None else None)
        outcome = session.execute()
    except RunError as exc:
        raise AtdError(str(exc)) from None
    return RunResult(outcome.succeeded, outcome.summary, outcome.end_state, tuple(v.path for v in outcome.visits),
                     outcome.sim_time, session.object_positions)


def run_campaign(spec: str | Path, only: dict[str, str] | None = None, trials: int | None = None) -> Iterator:
    """The trials of a campaign spec, run one by one in this process and judged by the
    simulator, as `atd campaign run` runs them (same seeds, so the same records): yields each
    TrialRecord as it ends. `only` narrows the cells ({"robot": "melfa"}), `trials` takes the
    first N of each. For many trials use `atd campaign run`: workers, a store, --resume."""
    from atd.campaign.cells import parse_only, plans
    from atd.campaign.spec import load_spec
    from atd.campaign.trial import run_trial

    loaded, found = load_spec(Path(spec))
    if loaded is None:
        raise AtdError(render_all(found))
    try:
        chosen = parse_only(tuple(f"{k}={v}" for k, v in (only or {}).items()))
    except ValueError as exc:
        raise AtdError(f"{spec}: {exc}") from None
    for plan in plans(loaded, chosen, trials):
        yield run_trial(plan)


def _named(robot: str | None) -> str:
    if robot is None:
        raise AtdError("an ATD needs a robot to run on: run(task, robot='melfa')")
    return robot
