"""The root click group and the exit codes every sub-command shares."""

import os
from pathlib import Path

import click

from atd import __version__

EXIT_OK = 0
EXIT_INVALID = 1  # the input file has errors
EXIT_USAGE = 2  # click's own code for a bad command line
EXIT_TASK_FAILED = 3  # a run ended in a failure state
EXIT_UNTRANSLATABLE = 4  # the robot cannot do the task


def unwritable(path: Path) -> str | None:
    """Why `path` could not be written, found before any work is done; None when it can."""
    folder = path.parent
    if not folder.is_dir():
        return f"the folder {folder} does not exist; create it or write elsewhere"
    if not os.access(folder, os.W_OK):
        return f"the folder {folder} is not writable; write elsewhere"
    return None


class OutputFile(click.Path):
    """A file a command will write, refused up front when its folder is missing or read-only."""

    def __init__(self) -> None:
        super().__init__(dir_okay=False, path_type=Path)

    def convert(self, value, param, ctx) -> Path:
        path = super().convert(value, param, ctx)
        problem = unwritable(path)
        if problem:
            self.fail(f"{path}: {problem}", param, ctx)
        return path


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="atd")
def main() -> None:
    """Describe a manipulation task once (ATD), translate it for a robot (ESTD), run it in simulation."""


@main.group(invoke_without_command=True)
@click.pass_context
def robots(ctx: click.Context) -> None:
    """The robots installed through factories (bare `atd robots` lists them)."""
    if ctx.invoked_subcommand is None:
        ctx.invoke(robots.get_command(ctx, "list"))


@main.group()
def campaign() -> None:
    """Trial campaigns: run a task many times under perturbed truth, judge each trial by the simulator."""
