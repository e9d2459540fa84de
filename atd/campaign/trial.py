"""One trial: translate what the robot believes, build what is true, run, judge.

Runs in a worker process. The belief (the ATD, with the cell's object in it) is
translated once per cell and kept; the robot and its scene are built afresh for every
trial, which costs a few milliseconds (measured in benchmarks/bench_campaign.py) and
leaves nothing of one trial in the next.
"""

from __future__ import annotations

import math
import time
import traceback
from dataclasses import replace
from functools import lru_cache
from pathlib import Path

import numpy as np

from atd.campaign.cells import TrialPlan
from atd.campaign.judge import BoxJudge, CapJudge, LiftJudge, PlaceJudge
from atd.campaign.perturbation import Truth
from atd.campaign.record import TASK_OBJECT, TrialRecord
from atd.campaign.unscrew import unscrew_measures
from atd.model import has_errors, load_task
from atd.model.diagnostics import render_all
from atd.model.estd import Estd, EstdState
from atd.model.files import OutputError
from atd.model.task import Location, Task
from atd.model.vocabulary import StateType
from atd.runtime.report import grasp_attempts
from atd.runtime.session import Run, belief_scene
from atd.sim.library import get as get_library
from atd.sim.scene import Scene
from atd.sim.world import Drop, World, WorldError
from factories.base import Factory, derived_target
from factories.registry import create
from translator import translate


class TrialError(Exception):
    """The trial cannot be run as planned (the task does not translate, ...)."""


@lru_cache(maxsize=64)
def believed_task(task_file: str, obj: str) -> Task:
    """The ATD the robot is given: the task file with the cell's object in it."""
    task, found = load_task(Path(task_file))
    if task is None or has_errors(found):
        raise TrialError(f"{task_file} does not validate:\n{render_all(found)}")
    if obj != TASK_OBJECT:
        from atd.campaign.objects import get

        pose = task.object.pose.as_array() if task.object is not None and task.object.pose is not None else None
        x, y = pose[:2, 3] if pose is not None else (0.10, 0.0)
        yaw = math.atan2(pose[1, 0], pose[0, 0]) if pose is not None else 0.0  # the task's object turned: so is the cell's
        task = task.model_copy(update={"object": get(obj).object_info(float(x), float(y), float(yaw))})
    return task


@lru_cache(maxsize=64)
def believed(task_file: str, robot: str, arm: str, grasp: str, obj: str) -> tuple[Estd, Factory]:
    """The ESTD the robot runs, from the ATD with the cell's object in it, and its factory."""
    task = believed_task(task_file, obj)
    factory = create(robot, arm, grasp=grasp)
    result = translate(task, factory)
    if result.estd is None:
        raise TrialError(f"{robot} ({arm}) cannot do {Path(task_file).name} with object '{obj}':\n"
                         f"{render_all(result.diagnostics)}")
    return result.estd, factory


def run_trial(plan: TrialPlan) -> TrialRecord:
    """The trial's record; an exception becomes an error record, so a campaign goes on."""
    started = time.perf_counter()
    record = TrialRecord(cell=plan.cell, index=plan.index, seed=plan.seed)
    try:
        _run(plan, record, started)
    except Exception as exc:  # noqa: BLE001 - any failure of one trial is that trial's result
        record.status, record.error = "error", _describe(exc)
    record.wall_time = time.perf_counter() - started
    if plan.recording and record.status == "ok" and not record.judged_succeeded:
        # Trials are deterministic: running it again with the recorder on records the same run.
        try:
            _run(plan, TrialRecord(cell=plan.cell, index=plan.index, seed=plan.seed), started, Path(plan.recording))
        except Exception as exc:  # noqa: BLE001 - a recording lost (a full disk, ...) never costs the trial's record
            record.recording_error = _describe(exc)
    return record


def trial_run(plan: TrialPlan, record: TrialRecord, recording: Path | None = None) -> tuple[Run, Estd]:
    """The trial's run, built as it will execute, and the ESTD the robot believes in; the
    values its perturbation drew are in `record` (before the run is built, which may fail).
    The perturbation changes the truth only (the world, the robot the simulator builds, the
    approach taken); the controllers know their robot from the factory's description (`Run`),
    so a perturbed hand never reaches them."""
    cell = plan.cell
    belief, factory = believed(plan.task_file, cell.robot, cell.arm, cell.grasp, cell.object)
    values = record.perturbation = plan.perturbation.draw(np.random.default_rng([plan.seed, 1]))
    scene = drawn_world(plan, belief) if plan.world else belief_scene(belief)
    if cell.object != TASK_OBJECT and scene.object is not None and not plan.world:
        from atd.campaign.objects import get

        found = get(cell.object)
        scene = replace(scene, object=(found.in_fixture() if plan.fixture else found).realize(scene.object))
    truth = plan.perturbation.apply(Truth(belief, scene, factory.robot), values)
    run = Run(truth.estd, factory, engine=cell.engine, seed=plan.seed, budget=plan.budget, scene=truth.scene,
              robot=truth.robot, record=recording, wall_budget=plan.wall_limit)
    return run, belief


def _run(plan: TrialPlan, record: TrialRecord, started: float, recording: Path | None = None) -> None:
    run, belief = trial_run(plan, record, recording)
    judge = _judge(plan, belief, run)
    record.setup_time = time.perf_counter() - started
    outcome = run.execute(afterwards=judge)
    if outcome.wall_clock_stopped:  # what the judge would read depends on this machine's speed
        raise TrialError(f"{outcome.summary} ({outcome.sim_time:.1f} s simulated): the machine ran it too slowly "
                         "for a result that holds on any other; not judged")
    if isinstance(judge, CapJudge):
        verdict = judge.verdict(outcome.succeeded)
        verdict.measurements.update(unscrew_measures(belief, run.trace.records, outcome.sim_time))
    else:
        verdict = judge.verdict
    if isinstance(judge, BoxJudge):
        attempts = [visit.entered for visit in grasp_attempts(belief, outcome.visits)]
        verdict.measurements.update(attempts=float(len(attempts)), **judge.by_remaining(attempts))
    record.task_succeeded = outcome.succeeded
    record.end_state = outcome.end_state
    record.summary = outcome.summary
    record.events = [{"t": r["t"], "transition": r["transition"], "event": r["event"],
                      "why": [c["reason"] for c in r["conditions"] if c.get("reason")]}
                     for r in run.trace.records if r["type"] == "event"]
    record.sim_time = outcome.sim_time
    record.judged_succeeded, record.judge_reason = verdict.succeeded, verdict.reason
    record.measurements = verdict.measurements


def drawn_world(plan: TrialPlan, belief: Estd) -> Scene:
    """The trial's world as the spec's `world` draws it: its objects chosen from the pool by
    the trial's seed (each once while the pool has enough), dropped (or laid, with a
    clearance) into the container and left to settle."""
    draw = plan.world
    assert draw is not None
    pool = draw.from_
    rng = np.random.default_rng([plan.seed, 3])
    chosen = [pool[i] for i in rng.choice(len(pool), draw.objects, replace=draw.objects > len(pool))]
    named = [name if not chosen[:i].count(name) else f"{name}_{chosen[:i].count(name) + 1}"
             for i, name in enumerate(chosen)]
    drop = Drop(tuple((n, get_library(c)) for n, c in zip(named, chosen)), draw.into, Location(plan.task_file, 0),
                draw.clearance)
    try:
        return World(objects=(), drops=(drop,), containers=()).scene(belief_scene(belief), plan.seed)
    except WorldError as exc:
        raise TrialError(f"the spec's world cannot be built around {Path(plan.task_file).name}: {exc}") from None


def _judge(plan: TrialPlan, belief: Estd, run: Run) -> LiftJudge | PlaceJudge | BoxJudge | CapJudge:
    """The judge the spec names, or the one the task's states call for: a world drawn into
    a container is judged by what is left in it, a task that unscrews by where the cap is, a
    task that places something by where it rests, any other by whether it was lifted."""
    if plan.judge == "box" or (plan.judge is None and plan.world):
        return _box_judge(plan, belief, run)
    unscrews = any(s.type is StateType.UNSCREW for _, machine in belief.walk() for s in machine.states)
    if plan.judge == "cap" or (plan.judge is None and unscrews):
        try:
            return CapJudge(run.robot)
        except ValueError as exc:
            raise TrialError(f"{plan.task_file}: {exc}; give a screw-capped library object (docs/objects.md)") from None
    places = [s for s in belief.states if s.type is StateType.PLACE and s.arm is not None
              and "target" in s.arm.params]
    kind = plan.judge or ("place" if places else "lift")
    if kind == "place":
        if not places:
            raise TrialError(f"{plan.task_file}: the place judge needs a place state with a target")
        return PlaceJudge(run.robot, _place_target(plan, places[-1]))
    return LiftJudge(run.robot)


def _place_target(plan: TrialPlan, place: EstdState) -> tuple[float, float, float]:
    """Where the task puts the object down: its place state's own target (the object's centre,
    the grasp's), not the ESTD's, which is for the TCP (the SDH2 pinches 19 mm off it)."""
    task = believed_task(plan.task_file, plan.cell.object)
    state = task.states_by_name.get(place.atd)
    if state is None:  # a place inside a sub-task: the ESTD's target is all there is
        return tuple(place.arm.params["target"])
    return state.target.position if state.target is not None else derived_target(state, task.object)


def _box_judge(plan: TrialPlan, belief: Estd, run: Run) -> BoxJudge:
    """The box judge, on the container the world is drawn into (or the task's first); it
    stops a run whose task cannot know the box is empty (every perceive is random blind,
    which never finds nothing) once it is."""
    containers = belief.environment.containers if belief.environment else ()
    name = plan.world.into if plan.world else (containers[0].name if containers else None)
    if name is None:
        raise TrialError(f"{plan.task_file}: the box judge needs a container")
    knows_empty = any(s.type is StateType.PERCEIVE and s.arm is not None and s.arm.params["method"] != "random_blind"
                      for _, machine in belief.walk() for s in machine.states)
    judge = BoxJudge(run.robot, name, None if knows_empty else run.executor.stop)
    run.observers.append(judge.watch)
    return judge


def _describe(exc: BaseException) -> str:
    if isinstance(exc, (TrialError, OutputError)):
        return str(exc)
    frame = traceback.extract_tb(exc.__traceback__)[-1] if exc.__traceback__ else None
    where = f" ({Path(frame.filename).name}:{frame.lineno})" if frame else ""
    return f"{type(exc).__name__}: {exc}{where}"
