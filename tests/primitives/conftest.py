"""Running primitives on simulated robots (the MuJoCo Melfa unless said otherwise): whole
examples through the translator, or small hand-made state machines that chain a few
controllers until a condition holds."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np
import pytest

from atd.campaign.cells import parse_only, plans
from atd.campaign.record import TrialRecord
from atd.campaign.spec import load_spec
from atd.campaign.trial import run_trial
from atd.model import load_task
from atd.model.estd import Condition, ConditionGroup, Controller, Estd, EstdEvent, EstdState, EstdTransition
from atd.model.vocabulary import EventType, StateType
from atd.runtime.executor import Executor, Outcome
from atd.sim import load_description, make_robot
from atd.sim.mujoco_engine import MujocoRobot
from atd.sim.scene import Scene, box_scene, scene_from_task
from atd.sim.simrobot import SimRobot
from factories.melfa.description import description
from factories.registry import create
from primitives.filters import held_wrench
from primitives.robot import Readings
from primitives.base import Context
from translator import translate

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
CAMPAIGNS = EXAMPLES / "campaigns"
Hook = Callable[[SimRobot, str, float], None]  # robot, current state path, sim time


def melfa(scene: Scene | None = None) -> MujocoRobot:
    return MujocoRobot(description(), scene if scene is not None else box_scene(), seed=0)


def leaf(kind: str, *sensors: str, **params) -> Condition:
    return Condition(kind=kind, sensors=sensors, params=params)


def both_done() -> ConditionGroup:
    return ConditionGroup(op="all", children=(leaf("arm_done"), leaf("hand_done")))


@dataclass
class Stage:
    """One state of a hand-made machine: controllers, and what ends it successfully."""

    arm: Controller
    hand: Controller
    until: Condition | ConditionGroup
    seconds: float = 10.0


def use(name: str, **params) -> Controller:
    return Controller(name=name, params=params)


def machine(*stages: Stage, failures: dict[str, tuple[EventType, Condition | ConditionGroup]] | None = None) -> Estd:
    """Stages in a row to `done`; each stage fails on its timeout, and on `failures`
    (stage name -> event, condition) where given."""
    names = [f"s{i}" for i in range(len(stages))] + ["done"]
    states = [EstdState(name=n, type=StateType.MOVE, atd=n, arm=s.arm, hand=s.hand) for n, s in zip(names, stages)]
    states += [EstdState(name="done", type=StateType.SUCCESS, atd="done"),
               EstdState(name="failed", type=StateType.FAILURE, atd="failed")]
    transitions = []
    for i, stage in enumerate(stages):
        name = names[i]
        transitions.append(_edge(name, names[i + 1], EventType.SUCCESS, stage.until))
        for failing, (event, condition) in (failures or {}).items():
            if failing == name:
                transitions.append(_edge(name, "failed", event, condition))
        transitions.append(_edge(name, "failed", EventType.TIMEOUT, leaf("timeout", seconds=stage.seconds), "#t"))
    return Estd(robot="melfa", arm="main", initial="s0", states=tuple(states), transitions=tuple(transitions))


def _edge(origin: str, destination: str, event: EventType, condition, suffix: str = "") -> EstdTransition:
    atd = f"{origin}->{destination}{suffix}"
    return EstdTransition(origin=origin, destination=destination, atd=atd,
                          events=(EstdEvent(type=event, atd=f"{atd}/{event.value}", condition=condition),))


def execute(estd: Estd, robot: SimRobot, hook: Hook | None = None, task=None,
            memory: dict | None = None) -> tuple[Outcome, Executor]:
    """Run an ESTD on a simulated robot; `memory`: the named values its states find already there."""
    ctx = Context(info=robot.info, params={}, object=task.object if task else None,
                  environment=task.environment if task else None, camera=robot.capture, memory=dict(memory or {}))
    executor = Executor(estd, robot, ctx, budget=60.0)
    progress = (lambda path, time, wall: hook(robot, path, time)) if hook else None
    return executor.run(progress=progress, every=1), executor


def run_example(path: Path, hook: Hook | None = None, robot: str = "melfa",
                arm: str | None = None, engine: str = "mujoco") -> tuple[Outcome, Executor, SimRobot]:
    """Translate an ATD for a robot (the Melfa by default) and run it in its own scene."""
    task, diagnostics = load_task(path)
    assert task is not None, diagnostics
    translation = translate(task, create(robot, arm))
    assert translation.ok, translation.diagnostics
    sim = make_robot(load_description(robot, arm), scene_from_task(task, path), engine)
    outcome, executor = execute(translation.estd, sim, hook, task)
    return outcome, executor, sim


def simulated(robot: str, arm: str | None = None, scene: Scene | None = None, engine: str = "mujoco") -> SimRobot:
    return make_robot(load_description(robot, arm), scene, engine)


def events(executor: Executor) -> list[dict]:
    return [r for r in executor.trace.records if r["type"] == "event"]


def tcp(robot: MujocoRobot) -> np.ndarray:
    return robot.read().tcp[:3, 3].copy()


@pytest.fixture
def robot() -> MujocoRobot:
    """The Melfa at home, 15 cm above a 5 cm box at (0.125, 0) on the table."""
    return melfa()


def last_reasons(executor: Executor) -> list[str]:
    """The controller reasons behind the last event that fired."""
    return [c["reason"] for c in events(executor)[-1]["conditions"] if c.get("reason")]


PRESET = EXAMPLES / "campaigns" / "table_3_3.toml"


def preset_trials(indices: tuple[int, ...], **cell: str) -> list:
    """Trials `indices` of one cell of the Table 3.3 preset (`cell`: robot, arm, engine,
    grasp, object, perturbation), run and judged as `atd campaign run` runs them: the same
    seeds, so the same sampled errors."""
    from atd.campaign.cells import parse_only, plans
    from atd.campaign.spec import load_spec
    from atd.campaign.trial import run_trial

    loaded, diagnostics = load_spec(PRESET)
    assert loaded is not None, diagnostics
    only = parse_only(tuple(f"{k}={v}" for k, v in cell.items()))
    return [run_trial(plan) for plan in plans(loaded, only, max(indices) + 1) if plan.index in indices]


def lifted_but_at_most_one(trials: list[tuple[str, int]], **cell: str) -> None:
    """Preset trials (object, index) that once failed to one defect: all but at most one now
    lift their object, and none is a false success. One may fail honestly: the robust grasp
    fails about one preset trial in eight, and which one turns on the last bit of a sum
    (docs/reliability.md), so a single pinned trial would test the arithmetic, not the fix."""
    records = [record for obj, index in trials for record in preset_trials((index,), **cell, object=obj)]
    assert not [r for r in records if r.task_succeeded and not r.judged_succeeded], "a false success"
    failed = [(r.cell.object, r.index, r.judge_reason, r.summary) for r in records if not r.judged_succeeded]
    assert len(failed) <= 1, failed


def generalisation_at(seed: int, folder: Path) -> Path:
    """`generalisation.toml` with another base seed, written in `folder` (its places' paths
    made absolute): a campaign trial nobody tuned on, pinned by a test."""
    spec = (CAMPAIGNS / "generalisation.toml").read_text()
    spec = spec.replace("base_seed = 8117", f"base_seed = {seed}").replace('"places/', f'"{CAMPAIGNS}/places/')
    (folder / "g.toml").write_text(spec)
    return folder / "g.toml"


def campaign_trial(spec: Path, index: int, *cell: str) -> TrialRecord:
    """Trial `index` of the one cell of `spec` that `cell` (`--only` terms) names, run here."""
    loaded, diagnostics = load_spec(spec)
    assert loaded is not None, diagnostics
    [record] = [run_trial(plan) for plan in plans(loaded, parse_only(cell), index + 1) if plan.index == index]
    return record


def pushed_still(robot: SimRobot) -> Callable[[float, tuple[float, float, float]], Readings]:
    """Readings of `robot` as it stands, at a time, with a force (N, world frame) on the hand
    beyond what the believed empty hand reads: a wrist pressed by what the hand touches."""
    still = robot.read()
    empty = still.wrench - held_wrench(robot.info.hand, still)

    def pushed(t: float, world: tuple[float, float, float]) -> Readings:
        force = still.tcp[:3, :3].T @ np.array(world)  # world frame to the sensor's
        return dataclasses.replace(still, time=t, wrench=empty + np.concatenate((force, np.zeros(3))))

    return pushed
