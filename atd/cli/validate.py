"""`atd validate`: check task files like a compiler; `atd schema`: the model as JSON Schema."""

from __future__ import annotations

import json
from pathlib import Path

import click

from atd.cli.app import EXIT_INVALID, EXIT_OK, main
from atd.model.bulk import cyclic_gc_paused
from atd.model.diagnostics import Diagnostic, Severity, render_all, sort_key
from atd.model.load import load_task
from atd.model.task import Task


@main.command()
@click.argument("files", nargs=-1, required=True, type=click.Path(path_type=Path))
@click.option("--format", "fmt", type=click.Choice(["text", "json"]), default="text", show_default=True,
              help="text for people, json for tools")
def validate(files: tuple[Path, ...], fmt: str) -> None:
    """Check ATD FILES and report every problem, each with file:line:col, a code and a hint.

    Exit status: 0 when no file has errors (warnings allowed), 1 when any has, 2 on usage error.
    """
    with cyclic_gc_paused():  # each task is freed as soon as it is read, not rescanned by the collector first
        reports: list[tuple[Path, list[Diagnostic]]] = [(f, load_task(f)[1]) for f in files]
    everything = [d for _, found in reports for d in found]
    errors = sum(d.severity is Severity.ERROR for d in everything)
    if fmt == "json":
        click.echo(json.dumps({
            "files": [
                {"file": str(f), "valid": not any(d.severity is Severity.ERROR for d in found),
                 "diagnostics": [d.as_dict() for d in sorted(found, key=sort_key)]}
                for f, found in reports
            ],
            "errors": errors,
            "warnings": len(everything) - errors,
        }, indent=2))
    else:
        if everything:
            click.echo(render_all(everything).rsplit("\n", 1)[0])
        warnings = len(everything) - errors
        click.echo(f"{len(files)} file{'s' * (len(files) != 1)} checked: "
                   f"{errors} error{'s' * (errors != 1)}, {warnings} warning{'s' * (warnings != 1)}")
    raise SystemExit(EXIT_INVALID if errors else EXIT_OK)


@main.command()
def schema() -> None:
    """Print the JSON Schema of the ATD model (the XML format itself is schemas/atd.xsd)."""
    click.echo(json.dumps(Task.model_json_schema(), indent=2, sort_keys=True))
