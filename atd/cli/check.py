"""`atd check TASK.xml...`: which installed robot (and arm) can do which task, and why not."""

from __future__ import annotations

import json
from pathlib import Path

import click

from atd.cli.app import EXIT_INVALID, EXIT_OK, main
from atd.model import load_task
from atd.model.diagnostics import Diagnostic, Severity, has_errors
from factories.base import Factory
from factories.registry import installed
from translator import translate


def every_robot() -> list[tuple[str, Factory]]:
    """One column per robot and arm: `tombatossals:left` etc. when a robot has several arms."""
    columns = []
    for name, entry in installed().items():
        factory_class = entry.load()
        for arm in factory_class.arms:
            label = name if len(factory_class.arms) == 1 else f"{name}:{arm.name}"
            columns.append((label, factory_class(arm=arm.name)))
    return columns


def _cell(verdict: dict) -> str:
    if verdict["translatable"]:
        warnings = len(verdict["warnings"])
        return "yes" + (f" ({warnings} warning{'s' * (warnings != 1)})" if warnings else "")
    return f"NO ({len(verdict['errors'])})"


def _first_lines(diagnostics: list[Diagnostic], errors: bool) -> list[str]:
    """The first line (file:line:col, code, message) of each error, or of each other diagnostic."""
    return [d.render().splitlines()[0] for d in diagnostics if (d.severity is Severity.ERROR) == errors]


def verdicts(tasks: tuple[Path, ...], robots: list[tuple[str, Factory]]) -> list[dict]:
    """Per task: whether it is a valid ATD, and per robot column whether it translates, with
    the first line of each error and warning (the matrix `atd check` prints, as data)."""
    found = []
    for path in tasks:
        task, problems = load_task(path)
        if task is None or has_errors(problems):
            found.append({"task": str(path), "valid": False, "errors": _first_lines(problems, errors=True), "robots": {}})
            continue
        columns = {}
        for label, factory in robots:
            diagnostics = translate(task, factory).diagnostics
            errors = _first_lines(diagnostics, errors=True)
            columns[label] = {"translatable": not errors, "errors": errors,
                              "warnings": _first_lines(diagnostics, errors=False)}
        found.append({"task": str(path), "valid": True, "robots": columns})
    return found


@main.command()
@click.argument("tasks", nargs=-1, required=True, type=click.Path(path_type=Path))
@click.option("--format", "fmt", type=click.Choice(["text", "json"]), default="text", show_default=True,
              help="the matrix as text, or as one JSON document (per task and robot: translatable, errors, warnings)")
def check(tasks: tuple[Path, ...], fmt: str) -> None:
    """Print a matrix of TASKS against every installed robot: translatable or not, and why not.

    Exit status: 0 when every task is a valid ATD (whatever the robots can do), 1 when one is not.
    """
    robots = every_robot()
    found = verdicts(tasks, robots)
    invalid = not all(row["valid"] for row in found)
    if fmt == "json":
        click.echo(json.dumps({"robots": [label for label, _ in robots], "tasks": found}, indent=2))
        raise SystemExit(EXIT_INVALID if invalid else EXIT_OK)
    rows, reasons = [], []
    for row in found:
        if not row["valid"]:
            rows.append((row["task"], *["invalid ATD"] * len(robots)))
            reasons.append(f"{row['task']}: invalid ATD; run: atd validate {row['task']}")
            continue
        rows.append((row["task"], *[_cell(row["robots"][label]) for label, _ in robots]))
        reasons += [f"{row['task']} x {label}: {error}" for label, _ in robots for error in row["robots"][label]["errors"]]
    header = ("task", *[label for label, _ in robots])
    widths = [max(len(r[i]) for r in [header, *rows]) for i in range(len(header))]
    for row in [header, *rows]:
        click.echo("  ".join(c.ljust(w) for c, w in zip(row, widths)).rstrip())
    if reasons:
        click.echo("\nwhy not:")
        for reason in reasons:
            click.echo(f"  {reason}")
    raise SystemExit(EXIT_INVALID if invalid else EXIT_OK)
