"""One simulated run: the robot and scene an ESTD asks for, the executor, and what
watches the run (trace, real-time pacing)."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from atd.model import Task
from atd.model.estd import Estd
from atd.runtime.executor import Executor, Observer, Outcome, Progress
from atd.runtime.trace import Trace
from atd.sim import ENGINES, UnknownRobot, load_description, make_robot
from atd.sim.scene import SceneError, scene_from_task
from primitives.base import Context

__all__ = ["ENGINES", "Run", "RunError"]


class RunError(Exception):
    """The run cannot start; the message says what to change."""


class _Pacer:
    """Holds the run back to real time, for watching it."""

    def __init__(self) -> None:
        self.start = time.perf_counter()

    def __call__(self, sim_time: float) -> None:
        ahead = sim_time - (time.perf_counter() - self.start)
        if ahead > 0:
            time.sleep(ahead)


class Run:
    def __init__(self, estd: Estd, engine: str = "mujoco", seed: int = 0, trace_path: Path | None = None,
                 realtime: bool = False, budget: float = 300.0) -> None:
        try:
            description = load_description(estd.robot, estd.arm)
            source = Path(estd.source) if estd.source else Path("task.xml")
            scene = scene_from_task(Task(object=estd.object, environment=estd.environment), source)
        except (UnknownRobot, SceneError) as exc:
            raise RunError(str(exc)) from None
        self.robot = make_robot(description, scene, engine, seed)
        self.trace = Trace(trace_path)
        context = Context(info=self.robot.info, params={}, object=estd.object, environment=estd.environment,
                          rng=np.random.default_rng(seed))
        self.executor = Executor(estd, self.robot, context, self.trace, budget=budget)
        self.observers: list[Observer] = [_Pacer()] if realtime else []

    def execute(self, progress: Progress | None = None) -> Outcome:
        try:
            return self.executor.run(progress, observers=tuple(self.observers))
        except BaseException:
            self.trace.discard()
            raise
        finally:
            self.robot.close()
