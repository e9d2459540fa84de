"""`atd graph FILE -o OUT.{dot,svg,png}`: draw an ATD or an ESTD."""

from __future__ import annotations

from pathlib import Path

import click

from atd.cli.app import EXIT_INVALID, EXIT_OK, EXIT_USAGE, OutputFile, guard_outputs, main, write_or_exit
from atd.graph.dot import GraphvizError
from atd.graph.layout import PictureTooBig
from atd.graph.render import FORMATS, Renderer, render
from atd.graph.source import read_graph
from atd.model.diagnostics import has_errors, render_all


@main.command()
@click.argument("file", type=click.Path(path_type=Path))
@click.option("-o", "--output", required=True, type=OutputFile(),
              help="the picture: OUT.dot (graphviz source), OUT.svg or OUT.png")
@click.option("--renderer", type=click.Choice([r.value for r in Renderer]), default=Renderer.AUTO.value,
              show_default=True, help="graphviz ('dot' on PATH), or builtin: the library layout (grandalf, and resvg "
              "for PNG); auto uses graphviz when it is installed")
@click.option("--conditions", is_flag=True, help="ESTD: show each event's concrete conditions and thresholds")
@click.option("--all-params", is_flag=True, help="ESTD: list every controller parameter, not only the key ones")
def graph(file: Path, output: Path, renderer: str, conditions: bool, all_params: bool) -> None:
    """Draw the ATD or ESTD in FILE: a box per state (type and key parameters), an arrow per
    transition (its events).

    Exit status: 0 written, 1 FILE is not a valid ATD or ESTD, 2 usage error (unknown output
    extension, graphviz asked for but missing, task or picture too big, output not writable).
    Nothing is written on error.
    """
    fmt = output.suffix.lower().lstrip(".")
    if fmt not in FORMATS:
        click.echo(f"error: cannot draw to '{output}': the output must end in "
                   f"{', '.join('.' + f for f in FORMATS[:-1])} or .{FORMATS[-1]}", err=True)
        raise SystemExit(EXIT_USAGE)
    guard_outputs({"-o": output}, [file])
    drawing, found = read_graph(file, conditions, all_params)
    if found:
        click.echo(render_all(found), err=True)
    if drawing is None or has_errors(found):
        click.echo(f"{file}: cannot be drawn; nothing written", err=True)
        raise SystemExit(EXIT_INVALID)
    try:
        data, drawn_by = render(drawing, fmt, Renderer(renderer))
    except GraphvizError as exc:
        click.echo(f"error: {exc}; install graphviz (https://graphviz.org/download/) or use "
                   f"--renderer builtin", err=True)
        raise SystemExit(EXIT_USAGE) from None
    except PictureTooBig as exc:
        click.echo(f"error: {file}: {exc}", err=True)
        raise SystemExit(EXIT_USAGE) from None
    write_or_exit(output, data)
    click.echo(f"wrote {output} ({len(drawing.nodes)} states, {len(drawing.edges)} transitions; {drawn_by})")
    raise SystemExit(EXIT_OK)
