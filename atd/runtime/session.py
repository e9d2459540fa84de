"""One simulated run: the robot and scene an ESTD asks for, the executor, and what
watches the run (trace, real-time pacing)."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from atd.model import Task
from atd.model.estd import Estd
from atd.runtime.executor import Executor, Observer, Outcome, Progress, build_problems
from atd.runtime.trace import Trace
from atd.sim import ENGINES, make_robot
from atd.sim.scene import SceneError, scene_from_task
from factories.base import Factory
from primitives.base import Context

__all__ = ["ENGINES", "Run", "RunError", "Unrunnable"]


class RunError(Exception):
    """The run cannot start; the message says what to change."""


class Unrunnable(RunError):
    """The ESTD asks for controllers or sensors this robot does not have."""

    def __init__(self, problems: list[str]) -> None:
        super().__init__("this ESTD does not fit the robot:\n" + "\n".join(f"  {p}" for p in problems))
        self.problems = problems


class _Pacer:
    """Holds the run back to real time, for watching it."""

    def __init__(self) -> None:
        self.start = time.perf_counter()

    def __call__(self, sim_time: float) -> None:
        ahead = sim_time - (time.perf_counter() - self.start)
        if ahead > 0:
            time.sleep(ahead)


class Run:
    def __init__(self, estd: Estd, factory: Factory, engine: str = "mujoco", seed: int = 0,
                 trace_path: Path | None = None, realtime: bool = False, budget: float = 300.0) -> None:
        """`factory` is the robot's factory: it knows the physical robot the ESTD was made for."""
        try:
            source = Path(estd.source) if estd.source else Path("task.xml")
            scene = scene_from_task(Task(object=estd.object, environment=estd.environment), source)
        except SceneError as exc:
            raise RunError(str(exc)) from None
        self.robot = make_robot(factory.robot, scene, engine, seed)
        context = Context(info=self.robot.info, params={}, object=estd.object, environment=estd.environment,
                          rng=np.random.default_rng(seed))
        problems = build_problems(estd, context)
        if problems:
            self.robot.close()
            raise Unrunnable(problems)
        self.trace = Trace(trace_path)
        self.executor = Executor(estd, self.robot, context, self.trace, budget=budget)
        self.observers: list[Observer] = [_Pacer()] if realtime else []

    def execute(self, progress: Progress | None = None) -> Outcome:
        """Run to the end; afterwards `object_position` is where the object came to rest."""
        try:
            outcome = self.executor.run(progress, observers=tuple(self.observers))
            self.object_position = tuple(float(v) for v in self.robot.object_pose()[:3, 3])
            return outcome
        except BaseException:
            self.trace.discard()
            raise
        finally:
            self.robot.close()
