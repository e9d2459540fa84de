"""`atd report` and `atd compare`: looking back at recorded runs."""

from __future__ import annotations

import json
from pathlib import Path

import click

from atd.cli.app import EXIT_INVALID, OutputFile, guard_outputs, main, usage_error, write_or_exit
from atd.review.compare import as_document, compare, entered, listed, render_text
from atd.review.load import Recording, RecordingError, load
from atd.review.page import report_page
from atd.review.plots import difference


def _load(path: Path) -> Recording:
    try:
        return load(path)
    except RecordingError as exc:
        click.echo(f"error: {exc}", err=True)
        raise SystemExit(EXIT_INVALID) from None


@main.command()
@click.argument("recording", metavar="RUN.mcap", type=click.Path(path_type=Path))
@click.option("-o", "--output", type=OutputFile(), default=None,
              help="the HTML file (default: RUN.html beside the recording)")
def report(recording: Path, output: Path | None) -> None:
    """One self-contained HTML page for a recorded run (atd run --record): the task graph
    with the path taken, a timeline, the signals with the events marked, and the readings
    that fired each event. Works offline: nothing is fetched from anywhere."""
    run = _load(recording)
    if output is None:  # RUN.html beside the recording (now read: a file, never '/'), which may be itself
        output = recording.with_suffix(".html")
        guard_outputs({"the default -o": output}, [recording])
    write_or_exit(output, report_page(run).encode())
    click.echo(f"wrote {output}")


@main.command("compare")
@click.argument("first", metavar="A.mcap", type=click.Path(path_type=Path))
@click.argument("second", metavar="B.mcap", type=click.Path(path_type=Path))
@click.option("--plot", type=OutputFile(), default=None, metavar="FILE.svg",
              help="also draw the differences per state and signal")
@click.option("--format", "fmt", type=click.Choice(["text", "json"]), default="text", show_default=True,
              help="the table as text, or as one JSON document")
def compare_runs(first: Path, second: Path, plot: Path | None, fmt: str) -> None:
    """Two runs of one task aligned state by state: time in each state, and per signal the
    difference of its mean (two seeds, two engines, a simulated and a real run)."""
    if plot is not None and plot.suffix.lower() != ".svg":
        usage_error(f"{plot}: --plot writes SVG; give a name ending in .svg")
    a, b = _load(first), _load(second)
    durations, rows = compare(a, b)
    if not durations:
        click.echo(f"error: {first} and {second} entered no state in common (A: {listed(entered(a), 5)}; B: "
                   f"{listed(entered(b), 5)}): there is nothing to set side by side; compare two runs of one task",
                   err=True)
        raise SystemExit(EXIT_INVALID)
    if plot is not None:
        write_or_exit(plot, difference(a, b, rows).encode())
    if fmt == "json":
        click.echo(json.dumps({**as_document(a, b, durations, rows), "plot": None if plot is None else str(plot)},
                              indent=2))
        return
    click.echo(render_text(a, b, durations, rows))
    if plot is not None:
        click.echo(f"plot: {plot}")
