"""`atd check TASK.xml...`: which installed robot (and arm) can do which task, and why not."""

from __future__ import annotations

from pathlib import Path

import click

from atd.cli.app import EXIT_INVALID, EXIT_OK, main
from atd.model import load_task
from atd.model.diagnostics import Severity, has_errors
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


@main.command()
@click.argument("tasks", nargs=-1, required=True, type=click.Path(path_type=Path))
def check(tasks: tuple[Path, ...]) -> None:
    """Print a matrix of TASKS against every installed robot: translatable or not, and why not.

    Exit status: 0 when every task is a valid ATD (whatever the robots can do), 1 when one is not.
    """
    robots = every_robot()
    rows, reasons, invalid = [], [], False
    for path in tasks:
        task, found = load_task(path)
        if task is None or has_errors(found):
            invalid = True
            rows.append((str(path), *["invalid ATD"] * len(robots)))
            reasons.append(f"{path}: invalid ATD; run: atd validate {path}")
            continue
        cells = []
        for label, factory in robots:
            result = translate(task, factory)
            errors = [d for d in result.diagnostics if d.severity is Severity.ERROR]
            warnings = len(result.diagnostics) - len(errors)
            if result.ok:
                cells.append("yes" + (f" ({warnings} warning{'s' * (warnings != 1)})" if warnings else ""))
            else:
                cells.append(f"NO ({len(errors)})")
                reasons += [f"{path} x {label}: {d.render().splitlines()[0]}" for d in errors]
        rows.append((str(path), *cells))
    header = ("task", *[label for label, _ in robots])
    widths = [max(len(r[i]) for r in [header, *rows]) for i in range(len(header))]
    for row in [header, *rows]:
        click.echo("  ".join(c.ljust(w) for c, w in zip(row, widths)).rstrip())
    if reasons:
        click.echo("\nwhy not:")
        for reason in reasons:
            click.echo(f"  {reason}")
    raise SystemExit(EXIT_INVALID if invalid else EXIT_OK)
