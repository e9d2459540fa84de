"""`atd translate TASK.xml --robot R`: write the ESTD for one robot, or say why it cannot be done."""

from __future__ import annotations

from pathlib import Path

import click

from atd.cli.app import (EXIT_INVALID, EXIT_OK, EXIT_UNTRANSLATABLE, EXIT_USAGE, OutputFile, guard_outputs, main,
                         usage_error, write_or_exit)
from atd.model import load_task
from atd.model.diagnostics import Diagnostic, Severity, has_errors, render_all
from atd.model.estd import Estd, describe
from atd.model.estd_xml import estd_to_json, estd_to_xml
from factories.base import GRASPS, Factory
from factories.config import ConfigError
from factories.registry import UnknownRobot, create
from translator import translate as translate_task


GRASP_OPTION = click.option(
    "--grasp", type=click.Choice(GRASPS), default="robust", show_default=True,
    help="robust: each robot's sensor-based grasp; naive: the thesis 3.4.1 baseline (close, squeeze)")


def _roles(ctx: click.Context, param: click.Parameter, values: tuple[str, ...]) -> dict[str, str]:
    """`--role holder=left`, any number of times: a role of the task -> an arm of the robot."""
    bound: dict[str, str] = {}
    for value in values:
        role, _, arm = value.partition("=")
        if not role or not arm:
            raise click.BadParameter(f"'{value}': give ROLE=ARM, e.g. --role holder=left")
        bound[role] = arm
    return bound


ROLE_OPTION = click.option(
    "--role", "roles", multiple=True, callback=_roles, metavar="ROLE=ARM",
    help="bind a role of a task for several arms to an arm (default: the roles in file order on --arm, then "
         "the robot's other arms)")


def make_factory(robot: str, arm: str | None, config: Path | None, grasp: str = "robust") -> Factory:
    """The factory, or a clean exit naming what is wrong with the robot, arm or config."""
    try:
        return create(robot, arm, config, grasp)
    except (UnknownRobot, ValueError) as exc:
        click.echo(f"error: {exc.args[0]}", err=True)
        raise SystemExit(EXIT_USAGE) from None
    except ConfigError as exc:
        click.echo(f"error: {exc}", err=True)
        raise SystemExit(EXIT_INVALID) from None


def default_output(task_path: Path, factory: Factory, fmt: str) -> Path:
    """`TASK.<robot>.estd.xml` beside the task; a non-default arm is named too."""
    robot = factory.name if factory.arm is factory.arms[0] else f"{factory.name}-{factory.arm.name}"
    return task_path.with_name(f"{task_path.stem}.{robot}.estd.{fmt}")


def summary(estd: Estd) -> str:
    """The short table: ATD node -> primitive, ATD edge -> conditions."""
    rows = [("ATD state", "type", "primitive", "arm controller", "hand controller")]
    for state in estd.states:
        rows.append((state.atd, state.type.value, state.primitive or ("sub-task" if state.machine else "-"),
                     state.arm.name if state.arm else "-", state.hand.name if state.hand else "-"))
    lines = _table(rows)
    edges = [("ATD transition", "event", "conditions")]
    for edge in estd.transitions:
        for event in edge.events:
            edges.append((edge.atd, event.type.value, describe(event.condition)))
    return "\n".join(lines + [""] + _table(edges))


def _table(rows: list[tuple[str, ...]]) -> list[str]:
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    return ["  ".join(cell.ljust(w) for cell, w in zip(row, widths)).rstrip() for row in rows]


def _report(diagnostics: list[Diagnostic]) -> None:
    if diagnostics:
        click.echo(render_all(diagnostics), err=True)


@main.command()
@click.argument("task", type=click.Path(path_type=Path))
@click.option("--robot", "-r", required=True, help="the robot to translate for (see `atd robots`)")
@click.option("--arm", default=None, help="which arm, for robots with more than one (default: the robot's first)")
@click.option("--config", type=click.Path(path_type=Path), default=None,  # read by the input guard
              help="TOML file with parameter overrides (see docs/estd.md)")
@click.option("-o", "--output", type=OutputFile(), default=None,
              help="where to write the ESTD (default: TASK.<robot>.estd.xml beside the task)")
@click.option("--format", "fmt", type=click.Choice(["xml", "json"]), default="xml", show_default=True)
@GRASP_OPTION
@ROLE_OPTION
@click.option("--quiet", "-q", is_flag=True, help="no summary table")
def translate(task: Path, robot: str, arm: str | None, config: Path | None, output: Path | None, fmt: str,
              grasp: str, roles: dict[str, str], quiet: bool) -> None:
    """Translate the ATD in TASK into an ESTD for ROBOT.

    Exit status: 0 written, 1 the ATD is invalid, 2 usage error, 4 the robot cannot do the
    task (nothing written; every reason is listed with its file:line).
    """
    factory = make_factory(robot, arm, config, grasp)
    atd_task, found = load_task(task)
    if atd_task is None or has_errors(found):
        _report(found)
        raise SystemExit(EXIT_INVALID)
    target = output or default_output(task, factory, fmt)  # named after a file now read: never '.' or '/'
    guard_outputs({"-o": target}, [task, *([config] if config else [])])
    try:
        result = translate_task(atd_task, factory, roles=roles)
    except ValueError as exc:  # a --role naming what is not there
        usage_error(f"--role: {exc}")
    warnings = [d for d in found if d.severity is Severity.WARNING] + result.diagnostics
    if result.estd is None:
        _report(warnings)
        click.echo(f"{task}: not translatable for {robot}; nothing written", err=True)
        raise SystemExit(EXIT_UNTRANSLATABLE)
    guard_outputs({"-o": target}, [task, *([config] if config else []), *result.estd.files()])
    write_or_exit(target, estd_to_json(result.estd) if fmt == "json" else estd_to_xml(result.estd))
    _report(warnings)
    if not quiet:
        click.echo(summary(result.estd))
        click.echo("")
    click.echo(f"wrote {target} ({factory.name}, {result.estd.arm_text})")
    raise SystemExit(EXIT_OK)
