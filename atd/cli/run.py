"""`atd run`: execute a task on a simulated robot and report the outcome in ATD terms."""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, NoReturn

import click

from atd.cli.run_output import Progress, document, next_step, where
from atd.cli.translate import GRASP_OPTION, ROLE_OPTION
from atd.cli.app import (EXIT_ENGINE_CRASHED, Engine, EXIT_INVALID, EXIT_OK, EXIT_TASK_FAILED, EXIT_UNTRANSLATABLE,
                         EXIT_USAGE, OutputFile, Ranged, guard_outputs, main, usage_error)
from atd.model import has_errors, load_task, ranges
from atd.model.diagnostics import render_all
from atd.model.estd import Estd
from atd.model.estd_xml import is_estd_file, read_estd
from atd.runtime.executor import Outcome
from atd.runtime.isolated import EngineCrash, in_child
from atd.runtime.report import grasp_attempts, summary
from atd.model.files import OutputError
from atd.runtime.session import InvalidScene, InvalidWorld, Run, RunError, Unrunnable, world_scene
from atd.sim.scene import WORKSPACE_CAMERA, Scene
from atd.sim.thread import CapState
from atd.sim.video import VideoError, parse_size
from factories.base import Factory
from factories.registry import UnknownRobot, create
from translator import translate


def _fail(message: str, code: int) -> NoReturn:
    click.echo(message, err=True)
    raise SystemExit(code)


def _factory(robot: str, arm: str | None, grasp: str = "robust") -> Factory:
    try:
        return create(robot, arm, grasp=grasp)
    except (UnknownRobot, ValueError) as exc:
        _fail(f"error: {exc.args[0]}", EXIT_USAGE)
        raise


def _load(task: Path, robot: str | None, arm: str | None, grasp: str,
          roles: dict[str, str]) -> tuple[Estd, Factory]:
    """The ESTD to run and its robot's factory: read as is, or translated from an ATD."""
    if is_estd_file(task):
        estd, found = read_estd(task)
        if estd is None:
            _fail(render_all(found), EXIT_INVALID)
        if robot and robot != estd.robot:
            _fail(f"error: {task} was translated for '{estd.robot}', not '{robot}'; "
                  f"translate the ATD again with --robot {robot}", EXIT_USAGE)
        return estd, _factory(estd.robot, estd.arm)
    atd_task, found = load_task(task)  # read first: a broken file is reported as what it is
    if atd_task is None or has_errors(found):
        _fail(render_all(found), EXIT_INVALID)
    if robot is None:
        _fail(f"error: {task} is an ATD; say which robot runs it with --robot (see `atd robots list`)", EXIT_USAGE)
    factory = _factory(robot, arm, grasp)
    try:
        result = translate(atd_task, factory, roles=roles)
    except ValueError as exc:  # a --role naming what is not there
        usage_error(f"--role: {exc}")
    if result.estd is None:
        _fail(render_all(result.diagnostics) + f"\n{task}: {robot} cannot do this task", EXIT_UNTRANSLATABLE)
    return result.estd, factory


def _world(estd: Estd, world_file: Path, seed: int) -> Scene:
    """The truth of `--world`, built before the engine starts: its errors are the input's."""
    try:
        return world_scene(estd, world_file, seed)
    except InvalidWorld as exc:
        _fail(str(exc), EXIT_INVALID)
    except InvalidScene as exc:
        _fail(f"error: {exc}", EXIT_INVALID)


@dataclass
class _Ran:
    """What the process that ran the engine sends back for the summary."""

    outcome: Outcome
    records: list[dict]
    object_positions: dict[str, tuple[float, float, float]]
    inside: dict[str, list[str]]
    inside_before: dict[str, list[str]]
    caps: dict[str, CapState]
    notes: list[str]


def _in_child(simulate: Callable[[], _Ran], progress: Progress) -> _Ran:
    """The run, in a child process; the progress line is cleared however it ends, before
    anything else is said."""
    try:
        return in_child(simulate)
    finally:
        progress.finish()


class VideoSize(click.ParamType):
    """--video-size WIDTHxHEIGHT, refused in one line (not click's usage text) when malformed."""

    name = "size"

    def convert(self, value, param, ctx) -> tuple[int, int]:
        if isinstance(value, tuple):  # the default
            return value
        try:
            return parse_size(value)
        except VideoError as exc:
            usage_error(str(exc))


class RecordRate(click.ParamType):
    """--rate: Hz of simulated time in its declared range, or 'tick' (None: every control tick)."""

    name = "rate"

    def convert(self, value, param, ctx) -> float | None:
        if value is None or value == "tick":
            return None
        return Ranged(ranges.RECORD_RATE).convert(value, param, ctx)


@main.command()
@click.argument("task", type=click.Path(path_type=Path))
@click.option("--robot", "-r", default=None, help="the robot (required for an ATD; an ESTD names its own)")
@click.option("--arm", default=None, help="which arm, for robots with more than one")
@click.option("--engine", type=Engine(), default="mujoco", show_default=True)
@click.option("--seed", type=Ranged(ranges.SEED, integer=True), default=0, show_default=True, help="seeds sensor noise: same seed, same trace")
@click.option("--trace", "trace_path", type=OutputFile(), default=None,
              help="write every state entry, exit and event as JSON lines")
@click.option("--video", type=OutputFile(), default=None,
              help="record the run from an offscreen camera, the state and simulated time drawn on each frame "
                   "(10 frames per simulated second): .gif, or .mp4 (needs ffmpeg: the video extra)")
@click.option("--video-size", type=VideoSize(), default="640x480", show_default=True, metavar="WxH",
              help="the video's width and height in pixels")
@click.option("--camera", default=WORKSPACE_CAMERA, show_default=True,
              help="the video's camera: 'workspace' (a free camera on the work area) or one of the robot's cameras")
@click.option("--record", type=OutputFile(), default=None, metavar="FILE.mcap",
              help="record every sensor reading, command, state and the simulator's ground truth as MCAP "
                   "(opens in Foxglove and PlotJuggler; see `atd report`)")
@click.option("--rate", "record_rate", type=RecordRate(), default="100", show_default=True, metavar="HZ|tick",
              help="how often --record samples, in Hz of simulated time, or 'tick' for every control tick")
@click.option("--viewer", is_flag=True, help="open the engine's window (needs a display; runs in real time)")
@click.option("--realtime", is_flag=True, help="run no faster than real time")
@click.option("--budget", type=Ranged(ranges.BUDGET), default=300.0, show_default=True,
              help="watchdog: simulated seconds before the run is stopped as a failure")
@click.option("--world", "world_file", type=click.Path(path_type=Path), default=None, metavar="WORLD.toml",
              help="what is truly on the table, whatever the task believes: placed objects, objects dropped "
                   "into a container (seeded by --seed), containers (see docs/worlds.md)")
@GRASP_OPTION
@ROLE_OPTION
@click.option("--quiet", "-q", is_flag=True, help="no live progress")
@click.option("--format", "fmt", type=click.Choice(["text", "json"]), default="text", show_default=True,
              help="the outcome as text, or as one JSON document (state path, events with their readings)")
def run(task: Path, robot: str | None, arm: str | None, engine: str, seed: int, trace_path: Path | None,
        video: Path | None, video_size: tuple[int, int], camera: str, record: Path | None,
        record_rate: float | None, viewer: bool, realtime: bool, budget: float, world_file: Path | None, grasp: str,
        roles: dict[str, str], quiet: bool, fmt: str) -> None:
    """Run TASK (an ATD, translated on the fly, or an ESTD) on a simulated robot.

    Exit status: 0 the task ended in a success state, 3 in a failure state (or the watchdog
    stopped it), 1 invalid input, 2 usage error, 4 the robot cannot do the task, 5 the
    engine crashed (it runs in a child process, so that is reported, not fatal).
    """
    inputs = [task, *([world_file] if world_file else [])]
    given = click.get_current_context().get_parameter_source
    shaping = [option for option, name in (("--video-size", "video_size"), ("--camera", "camera"))
               if given(name) is not click.core.ParameterSource.DEFAULT]
    if shaping and video is None:
        usage_error(f"{' and '.join(shaping)}: there is no video to shape; give --video FILE.gif too")
    guard_outputs({"--trace": trace_path, "--video": video, "--record": record}, inputs)
    if record is not None and record.suffix.lower() != ".mcap":
        usage_error(f"{record}: --record writes MCAP; give a file name ending in .mcap")
    estd, factory = _load(task, robot, arm, grasp, roles)
    guard_outputs({"--trace": trace_path, "--video": video, "--record": record}, [*inputs, *estd.files()])
    truth = _world(estd, world_file, seed) if world_file else None

    def simulate() -> _Ran:
        session = Run(estd, factory, engine=engine, seed=seed, trace_path=trace_path, realtime=realtime,
                      budget=budget, video=video, video_size=video_size, camera=camera, viewer=viewer, scene=truth,
                      record=record, record_rate=record_rate)
        outcome = session.execute(progress)
        return _Ran(outcome, session.trace.records, session.object_positions, session.inside, session.inside_before,
                    session.caps, session.notes)

    progress = Progress(quiet)
    try:
        ran = _in_child(simulate, progress)
    except Unrunnable as exc:
        _fail(f"error: {exc}", EXIT_UNTRANSLATABLE)
    except InvalidScene as exc:
        _fail(f"error: {exc}", EXIT_INVALID)
    except RunError as exc:
        _fail(f"error: {exc}", EXIT_USAGE)
    except OutputError as exc:
        usage_error(str(exc))
    except EngineCrash as exc:
        _fail(f"error: the {engine} engine crashed ({exc}) running {task}; "
              f"try --engine {'pybullet' if engine == 'mujoco' else 'mujoco'}", EXIT_ENGINE_CRASHED)
    outputs = {"trace": trace_path, "record": record, "video": video}
    if fmt == "json":
        about = {"task": str(task), "robot": estd.robot, "arm": estd.arm, "engine": engine, "seed": seed}
        click.echo(json.dumps(document(about, ran.outcome, ran.records, ran.object_positions, ran.inside, outputs,
                                       ran.notes, ran.caps), indent=2))
        raise SystemExit(EXIT_OK if ran.outcome.succeeded else EXIT_TASK_FAILED)
    title = f"{task.name} on {estd.robot} ({estd.arm_text}) in {engine}, seed {seed}"
    click.echo(summary(ran.outcome, ran.records, title))
    for line in where(ran.object_positions, ran.inside, ran.inside_before, ran.caps):
        click.echo(line)
    attempts = len(grasp_attempts(estd, ran.outcome.visits))
    if attempts:
        click.echo(f"grasp attempts: {attempts} in {ran.outcome.sim_time:.1f} s of simulated time")
    if trace_path:
        click.echo(f"trace: {trace_path}")
    if record:
        click.echo(f"recording: {record} (see it with: atd report {record})")
    for note in ran.notes:
        click.echo(note)
    command = ["atd", "run", str(task), *(["--robot", robot] if robot else []), *(["--arm", arm] if arm else [])]
    click.echo(next_step(command, record, video, ran.outcome.succeeded))
    raise SystemExit(EXIT_OK if ran.outcome.succeeded else EXIT_TASK_FAILED)
