"""The root click group and the exit codes every sub-command shares."""

import click

from atd import __version__

EXIT_OK = 0
EXIT_INVALID = 1  # the input file has errors
EXIT_USAGE = 2  # click's own code for a bad command line
EXIT_TASK_FAILED = 3  # a run ended in a failure state
EXIT_UNTRANSLATABLE = 4  # the robot cannot do the task


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
