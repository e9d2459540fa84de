"""`atd campaign report` and `atd campaign export`: read what a campaign stored."""

from __future__ import annotations

from pathlib import Path

import click

from atd.campaign.export import EXPORT_FORMATS, export
from atd.campaign.formats import FORMATS, render
from atd.campaign.record import DIMENSIONS, TrialRecord
from atd.campaign.report import build_report, parse_by
from atd.campaign.store import Store, StoreError
from atd.cli.app import EXIT_INVALID, EXIT_OK, EXIT_USAGE, OutputFile, campaign, write_or_exit

PLOT_SUFFIXES = (".png", ".svg")


def _stored(store: Path) -> list[TrialRecord]:
    try:
        with Store.open_read(store) as opened:
            return opened.records()
    except StoreError as exc:
        click.echo(f"error: {exc}", err=True)
        raise SystemExit(EXIT_INVALID) from None


@campaign.command()
@click.argument("store", type=click.Path(path_type=Path))
@click.option("--format", "fmt", type=click.Choice(FORMATS), default="table", show_default=True,
              help="table for a terminal, markdown for a README, json or csv for tools")
@click.option("--by", "by_text", default=None, metavar="DIM[,DIM...]",
              help=f"group trials by these dimensions ({', '.join(DIMENSIONS)}); default: all, one group per cell")
@click.option("--plot", type=OutputFile(), default=None, metavar="FILE.png|FILE.svg",
              help="also draw success rates with their intervals (per --by group, per condition when --by "
                   "is not given) and success against approach-error size")
@click.option("-o", "--output", type=OutputFile(), default=None, help="write the report to this file, not stdout")
def report(store: Path, fmt: str, by_text: str | None, plot: Path | None, output: Path | None) -> None:
    """Summarise the campaign STORE: per group n, successes (the judge's verdict), success rate
    with its 95% Wilson interval, false successes and failures, trials that could not be run;
    per condition over all objects; and thesis Table 3.3 beside ours when the campaign has its shape.

    Exit status: 0 written, 1 STORE is missing or not a campaign store, 2 usage error.
    """
    try:
        by = parse_by(by_text) if by_text is not None else DIMENSIONS
    except ValueError as exc:
        click.echo(f"error: --by: {exc}", err=True)
        raise SystemExit(EXIT_USAGE) from None
    if plot is not None and plot.suffix.lower() not in PLOT_SUFFIXES:
        click.echo(f"error: cannot draw to '{plot}': --plot must end in .png or .svg", err=True)
        raise SystemExit(EXIT_USAGE)
    records = _stored(store)
    built = build_report(records, by)
    text = render(built, fmt)
    if output is None:
        click.echo(text, nl=False)
    else:
        write_or_exit(output, text.encode())
        click.echo(f"wrote {output} ({len(built.groups)} groups of {built.trials} trials)", err=True)
    if plot is not None:
        from atd.campaign.plots import draw_report  # matplotlib only when a plot is asked for

        groups = built.groups if by_text is not None else built.conditions
        write_or_exit(plot, draw_report(records, groups, plot.suffix.lower().lstrip(".")))
        click.echo(f"wrote {plot}", err=True)
    raise SystemExit(EXIT_OK)


@campaign.command("export")
@click.argument("store", type=click.Path(path_type=Path))
@click.option("--format", "fmt", type=click.Choice(EXPORT_FORMATS), required=True,
              help="csv: a row per trial, sampled values and measurements as columns; json: a list of trials")
@click.option("-o", "--output", type=OutputFile(), required=True, help="the file to write")
def export_command(store: Path, fmt: str, output: Path) -> None:
    """Write every trial of the campaign STORE, every field, for other tools.

    Exit status: 0 written, 1 STORE is missing or not a campaign store, 2 usage error.
    """
    records = _stored(store)
    write_or_exit(output, export(records, fmt).encode())
    click.echo(f"wrote {output} ({len(records)} trials)", err=True)
    raise SystemExit(EXIT_OK)
