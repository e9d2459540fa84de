"""One simulated run: the robot and scene an ESTD asks for, the executor, and what
watches the run (trace, video, viewer, real-time pacing)."""

from __future__ import annotations

import json
import os
import time
from dataclasses import replace
from pathlib import Path
from typing import Callable

import numpy as np

from atd.model import Task
from atd.model.estd import Estd
from atd.model.diagnostics import Diagnostic, render_all
from atd.model.estd_xml import estd_to_xml
from atd.model.files import InputError, read_capped
from atd.model.xmlsafe import MAX_BYTES
from atd.runtime.executor import WALL_BUDGET, Executor, Observer, Outcome, Progress, build_problems
from atd.runtime.recording import DEFAULT_RATE, RECORDING_FORMAT, Recording
from atd.runtime.trace import Trace
from atd.sim import ENGINES, make_arms
from atd.sim.scene import WORKSPACE_CAMERA, Scene, SceneError, scene_from_task
from atd.sim.simrobot import SimRobot
from atd.sim.video import DEFAULT_SIZE, VideoError, check_camera, check_video_path
from atd.sim.video_recorder import Recorder
from atd.sim.world import WorldError, load_world
from factories.base import Factory
from factories.description import RobotDescription
from primitives.base import Context

__all__ = ["ENGINES", "InvalidScene", "InvalidWorld", "Run", "RunError", "Unrunnable", "belief_scene", "world_scene"]


class RunError(Exception):
    """The run cannot start; the message says what to change."""


class InvalidScene(RunError):
    """The task's object or environment cannot be simulated (a missing or broken mesh)."""


class InvalidWorld(InvalidScene):
    """A world file that cannot be built; its diagnostics say where and why."""

    def __init__(self, diagnostics: list[Diagnostic]) -> None:
        super().__init__(render_all(diagnostics))
        self.diagnostics = diagnostics


class Unrunnable(RunError):
    """The ESTD asks for controllers or sensors this robot does not have."""

    def __init__(self, problems: list[str]) -> None:
        super().__init__("this ESTD does not fit the robot:\n" + "\n".join(f"  {p}" for p in problems))
        self.problems = problems

    def __reduce__(self):
        """Rebuilt from its problems, when it crosses from the process that ran the engine."""
        return Unrunnable, (self.problems,)


def belief_scene(estd: Estd) -> Scene:
    """The world as the ESTD describes it."""
    try:
        source = Path(estd.source) if estd.source else Path("task.xml")
        return scene_from_task(Task(known_objects=estd.known_objects, environment=estd.environment), source)
    except SceneError as exc:
        raise InvalidScene(str(exc)) from None


def world_scene(estd: Estd, world_file: Path, seed: int) -> Scene:
    """The truth a world file describes, around the world the ESTD believes in (its obstacles
    and containers); the drops are drawn from the run's `seed`. InvalidWorld when it cannot be built."""
    world, found = load_world(world_file)
    if world is None:
        raise InvalidWorld(found)
    try:
        return world.scene(belief_scene(estd), seed)
    except WorldError as exc:
        raise InvalidWorld(exc.diagnostics) from None


def _run_info(estd: Estd, engine: str, seed: int) -> dict[str, str]:
    """What a recording says about the run it holds."""
    return {"atd.run": json.dumps({"format": RECORDING_FORMAT, "robot": estd.robot, "arm": estd.arm, "engine": engine, "seed": seed,
                                   "task": estd.source or ""})}


def _attachments(estd: Estd) -> dict[str, bytes]:
    """The ESTD that ran (and the ATD it came from, where it can be read), kept in the
    recording so a report can draw the task without the files beside it."""
    found = {"task.estd.xml": estd_to_xml(estd)}
    if estd.source:
        try:
            found["task.atd.xml"] = read_capped(Path(estd.source), MAX_BYTES)
        except InputError:
            pass  # the recording still holds the ESTD, which names every ATD element
    return found


class _Video:
    """Keeps a frame every `FRAME_PERIOD` of simulated time, labelled with the state the
    executor is in; written when the run ends."""

    def __init__(self, robot: SimRobot, others: tuple[SimRobot, ...], executor: Executor, recorder: Recorder) -> None:
        self.robot, self.others, self.executor, self.recorder = robot, others, executor, recorder

    def __call__(self, sim_time: float) -> None:
        self.recorder(self.robot, self.executor.machine.innermost().visit.path, self.others)

    def write(self) -> str:
        """What became of the video, for the user."""
        return self.recorder.save()

    def abandon(self) -> None:
        self.recorder.abandon()


class _Viewer:
    """The engine's interactive window, kept in step with the run about 60 times a second."""

    def __init__(self, robot) -> None:
        self.robot = robot
        self.next = 0.0

    @staticmethod
    def check_display() -> None:
        if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
            raise RunError("--viewer needs a display (none is set: DISPLAY is empty); "
                           "record a --video run.mp4 or run.gif instead")

    def __call__(self, sim_time: float) -> None:
        if sim_time >= self.next:
            self.robot.show()
            self.next = sim_time + 1 / 60


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
                 trace_path: Path | None = None, realtime: bool = False, budget: float = 300.0,
                 wall_budget: float = WALL_BUDGET,
                 video: Path | None = None, viewer: bool = False, scene: Scene | None = None,
                 robot: RobotDescription | None = None, record: Path | None = None,
                 record_rate: float | None = DEFAULT_RATE, video_size: tuple[int, int] = DEFAULT_SIZE,
                 camera: str = WORKSPACE_CAMERA) -> None:
        """`factory` is the robot's factory: it knows the physical robot the ESTD was made for,
        and its description is all the controllers know of their robot (`context.info`).
        `scene` and `robot` are the truth where it differs from what the ESTD and the factory
        believe (a campaign's perturbed trial): by default the world is built from the ESTD's
        object and environment, and the robot is the factory's; the simulator alone sees them. `record` writes the run's
        signals to MCAP at `record_rate` Hz of simulated time (None: every tick); `video` is
        rendered at `video_size` (width, height) from `camera` (see `atd.sim.video.cameras`).
        An ESTD whose states run on several arms (a task that names roles) gets them all in one
        world; `robot` is then the truth of the ESTD's own arm."""
        arms = (factory.arm.name,) + tuple(a for a in estd.arms if a != factory.arm.name)
        if video is not None:
            try:
                check_video_path(video)
                check_camera(camera, robot or factory.robot)
            except VideoError as exc:
                raise RunError(str(exc)) from None
        if scene is None:
            scene = belief_scene(estd)
        if viewer:
            _Viewer.check_display()
        beliefs = tuple(factory.on_arm(a).robot for a in arms)
        truths = (robot or factory.robot,) + beliefs[1:]  # a campaign perturbs the ESTD's own arm only
        filming = Recorder(video, video_size, camera) if video is not None else None
        if filming:  # it builds its copy of the robot while this process builds the run
            filming.start(truths, scene, engine)
        try:
            robots = make_arms(truths, scene, engine, seed, window=viewer,
                               beliefs=beliefs)
        except SceneError as exc:
            if filming:
                filming.abandon()
            raise InvalidScene(str(exc)) from None
        except ValueError as exc:  # an engine this installation lacks
            raise RunError(str(exc)) from None
        self.robot = robots[0]
        self.others = others = dict(zip(arms[1:], robots[1:]))  # the robot's other arms the task uses, by name
        self.notes: list[str] = [str(self.robot.settling)] if self.robot.settling else []  # for the user
        self.inside_before = {c.name: self.robot.objects_inside(c.name) for c in self.robot.scene.containers}
        # The controllers' model of their robot is the factory's (the belief), never the simulated truth's.
        self.context = context = Context(info=factory.info, params={}, object=estd.object,
                                         environment=estd.environment, rng=np.random.default_rng(seed),
                                         camera=self.robot.capture)
        known = {name: factory.on_arm(name).info for name in others}
        problems = build_problems(estd, context, {name: replace(context, info=known[name], camera=r.capture)
                                                  for name, r in others.items()})
        if problems:
            self.robot.close()
            if filming:
                filming.abandon()
            raise Unrunnable(problems)
        self.trace = Trace()
        self.trace_path = trace_path
        self.executor = Executor(estd, self.robot, context, self.trace, budget=budget, wall_budget=wall_budget,
                                 others={name: (r, known[name]) for name, r in others.items()})
        self.video = _Video(self.robot, tuple(others.values()), self.executor, filming) if filming else None
        self.viewer = _Viewer(self.robot) if viewer else None
        self.recorder = Recording(record, self.robot, self.executor, self.trace, tuple(self.robot.recorded_poses()), record_rate,
                                 _run_info(estd, engine, seed), _attachments(estd)) if record is not None else None
        self.observers: list[Observer] = [o for o in (self.video, self.viewer, self.recorder) if o]
        if realtime or viewer:
            self.observers.append(_Pacer())

    def execute(self, progress: Progress | None = None,
                afterwards: Callable[[SimRobot], None] | None = None) -> Outcome:
        """Run to the end; afterwards `object_positions` is where each object came to rest,
        `object_position` the first's (None when there is none), `inside` which objects
        each container holds (`inside_before`: as the run began), and `caps` the truth about
        each screw cap (`SimRobot.caps`). `afterwards` gets the robot once the task has ended, before it
        is released: a campaign's judge looks at the world there. The trace and video are
        written last; OutputError when one cannot be."""
        try:
            outcome = self.executor.run(progress, observers=tuple(self.observers))
            if afterwards is not None:
                afterwards(self.robot)
            self.object_positions = {name: tuple(float(v) for v in pose[:3, 3])
                                     for name, pose in self.robot.object_poses().items()}
            self.object_position = next(iter(self.object_positions.values()), None)
            self.inside = {c.name: self.robot.objects_inside(c.name) for c in self.robot.scene.containers}
            self.caps = self.robot.caps()
            if self.trace_path:
                self.trace.save(self.trace_path)
            if self.recorder:
                self.recorder.finish(outcome)
            if self.video:
                self.notes.append(self.video.write())
            return outcome
        finally:
            for unfinished in (self.recorder, self.video):
                if unfinished:
                    unfinished.abandon()
            self.robot.close()
