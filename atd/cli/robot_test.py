"""`atd robots test`: the self-test anyone writing a factory runs on their robot model."""

from __future__ import annotations

import sys
from pathlib import Path

import click

from atd.cli.app import EXIT_OK, EXIT_TASK_FAILED, Engine, OutputFile, Ranged, robots, usage_error
from atd.model import ranges
from atd.model.files import OutputError


@robots.command("test")
@click.argument("robot")
@click.option("--arm", default=None, help="Which arm (e.g. left, right; default: the robot's first).")
@click.option("--engine", type=Engine(), default="mujoco", show_default=True)
@click.option("--seed", type=Ranged(ranges.SEED, integer=True), default=0, show_default=True, help="Seed of the sensor noise.")
@click.option("--video", type=OutputFile(), default=None, help="Record the grasp as a video (.gif, or .mp4 with ffmpeg).")
def robot_test(robot: str, arm: str | None, engine: str, seed: int, video: Path | None) -> None:
    """Check a simulated ROBOT: kinematics, limits, holding, a grasp, force-torque and tactile sensors.

    Exits 0 only when every check passes.
    """
    from atd.sim import UnknownRobot, load_description
    from atd.sim.selftest import run_all
    from atd.sim.video import VideoError, check_video_path
    from atd.sim.video_recorder import Recorder

    try:
        description = load_description(robot, arm)
    except (UnknownRobot, ValueError) as exc:
        usage_error(str(exc))
    if video is not None:
        try:
            check_video_path(video)
        except VideoError as exc:
            usage_error(str(exc))

    recorder = Recorder(video) if video is not None else None
    click.echo(f"atd robots test {description.label} on {engine} (seed {seed})")
    checks = run_all(description, engine, seed, recorder)
    width = max(len(c.name) for c in checks)
    for c in checks:
        click.echo(f"  {c.name:<{width}}  {'PASS' if c.passed else 'FAIL'}  {c.measured}")
    passed = sum(c.passed for c in checks)
    click.echo(f"{passed}/{len(checks)} checks passed")
    if video is not None:
        try:
            click.echo(recorder.save())
        except OutputError as exc:
            usage_error(str(exc))
    sys.exit(EXIT_OK if passed == len(checks) else EXIT_TASK_FAILED)
