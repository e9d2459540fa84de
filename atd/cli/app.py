"""The root click group and the exit codes every sub-command shares."""

from __future__ import annotations

import faulthandler
import importlib
from pathlib import Path
from typing import TYPE_CHECKING, Iterable, Mapping, NoReturn

import click

from atd import __version__

if TYPE_CHECKING:
    from atd.model import ranges

# `atd --help` imports this module and click alone: atd.model (pydantic, lxml, numpy) is
# imported by the functions below that need it, when a command runs.

EXIT_OK = 0
EXIT_INVALID = 1  # the input file has errors
EXIT_USAGE = 2  # click's own code for a bad command line
EXIT_TASK_FAILED = 3  # a run ended in a failure state
EXIT_UNTRANSLATABLE = 4  # the robot cannot do the task
EXIT_ENGINE_CRASHED = 5  # the engine died in its C code (atd run)


class OutputFile(click.Path):
    """A file a command will write, refused up front when it could not be written safely (see
    `atd.model.files.output_problem`): one line and exit 2, as every other output refusal and
    write error is, not click's usage text."""

    def __init__(self) -> None:
        super().__init__(path_type=Path)  # a directory too is refused below, in the same words

    def convert(self, value, param, ctx) -> Path:
        from atd.model.files import output_problem

        path = super().convert(value, param, ctx)
        problem = output_problem(path)
        if problem:
            usage_error(f"{param.opts[0] if param else 'output'} {path}: {problem}")
        return path


class Ranged(click.ParamType):
    """A number on the command line, checked against its declared range (atd.model.ranges)."""

    def __init__(self, allowed: ranges.Range, integer: bool = False) -> None:
        self.allowed, self.integer = allowed, integer
        self.name = f"{'integer' if integer else 'number'} in {allowed}"

    def convert(self, value, param, ctx) -> float | int:
        from atd.model import ranges

        try:
            text = str(value)  # a default is already a number
            number = ranges.integer(text) if self.integer else ranges.numbers([text.strip()])[0]
        except ValueError:
            self.fail(f"'{value}' is not {'an integer' if self.integer else 'a number'}; give one in {self.allowed}",
                      param, ctx)
        problem = self.allowed.problem(number)
        if problem:
            self.fail(problem, param, ctx)
        return number


class Engine(click.Choice):
    """A physics engine's name; PyBullet, an optional install, refused with the fix where it
    is missing (atd/sim/optional.py)."""

    def __init__(self) -> None:
        super().__init__(["mujoco", "pybullet"])  # atd.sim.ENGINES, not imported for `atd --help`

    def convert(self, value, param, ctx) -> str:
        engine = super().convert(value, param, ctx)
        if engine == "pybullet":
            from atd.sim.optional import pybullet_installed, pybullet_missing

            if not pybullet_installed():
                self.fail(pybullet_missing("--engine pybullet"), param, ctx)
        return engine


def usage_error(message: str) -> NoReturn:
    """One line on stderr and exit 2: the command line asked for something that cannot be done."""
    click.echo(f"error: {message}", err=True)
    raise SystemExit(EXIT_USAGE)


def guard_outputs(outputs: Mapping[str, Path | None], inputs: Iterable[Path] = ()) -> None:
    """Exit 2 before any work when an output would overwrite an input, another output or
    something that is not a regular file."""
    from atd.model.files import output_problems

    problems = output_problems(outputs, inputs)
    if problems:
        usage_error("; ".join(problems))


def write_or_exit(path: Path, data: bytes) -> None:
    """Write an output atomically, or exit 2 with one line and nothing left behind."""
    from atd.model.files import OutputError, write_output

    try:
        write_output(path, data)
    except OutputError as exc:
        usage_error(str(exc))


class GuardedCommand(click.Command):
    """The class of every `atd` command: it refuses an option given twice (e.g. two `-o`:
    click would silently keep the last), and before the command does anything, an output
    (an `OutputFile` option) naming one of the paths the command line gives it to read, or
    the same file as another output. A command checks what it learns later (sub-tasks,
    meshes, an output's default name) with `guard_outputs` itself."""

    def parse_args(self, ctx: click.Context, args: list[str]) -> list[str]:
        if not ctx.resilient_parsing:
            _, _, order = self.make_parser(ctx).parse_args(args=list(args))
            once = [p for p in order if isinstance(p, click.Option) and not p.multiple and not p.count]
            repeated = next((p for p in once if once.count(p) > 1 and not p.is_flag), None)
            if repeated is not None:
                raise click.UsageError(f"{repeated.opts[-1]} is given more than once; give it once", ctx)
        return super().parse_args(ctx, args)

    def invoke(self, ctx: click.Context):
        outputs = {p.opts[0]: ctx.params.get(p.name) for p in self.params if isinstance(p.type, OutputFile)}
        inputs = [path for p in self.params if isinstance(p.type, click.Path) and not isinstance(p.type, OutputFile)
                  for path in _paths(ctx.params.get(p.name))]
        guard_outputs(outputs, inputs)
        return super().invoke(ctx)


def _paths(value: object) -> list[Path]:
    """The paths of a parameter's value: none, one, or several (an argument with nargs=-1)."""
    if value is None:
        return []
    return [Path(v) for v in value] if isinstance(value, (tuple, list)) else [Path(value)]


class Commands(click.Group):
    """The group class of `atd`: its commands refuse repeated options, its sub-groups too.

    A command's module is imported when the command is asked for, not at start-up: `atd
    validate` then loads neither the engines nor the campaign tools, and `atd --help` loads
    none of them, listing each command with the one line the group keeps for it here.
    """

    command_class = GuardedCommand

    def __init__(self, *args, lazy: Mapping[str, tuple[str, str]] | None = None, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self.lazy = dict(lazy or {})  # command name -> (the module that registers it here, its one line)

    def list_commands(self, ctx: click.Context) -> list[str]:
        return sorted({*self.commands, *self.lazy})

    def get_command(self, ctx: click.Context, name: str) -> click.Command | None:
        if name not in self.commands and name in self.lazy:
            importlib.import_module(self.lazy[name][0])
        command = super().get_command(ctx, name)
        if command is not None and name in self.lazy:  # one line for it, listed before or after it loads
            command.short_help = self.lazy[name][1]
        return command

    def format_commands(self, ctx: click.Context, formatter: click.HelpFormatter) -> None:
        """The commands and their one line each, without importing a command's module."""
        names = [name for name in self.list_commands(ctx) if name in self.lazy or not self.commands[name].hidden]
        limit = formatter.width - 6 - max(map(len, names), default=0)  # as click's own listing
        rows = [(name, self.lazy[name][1] if name in self.lazy else self.commands[name].get_short_help_str(limit))
                for name in names]
        if rows:
            with formatter.section("Commands"):
                formatter.write_dl(rows)


Commands.group_class = Commands


@click.group(cls=Commands, context_settings={"help_option_names": ["-h", "--help"]}, lazy={
    "validate": ("atd.cli.validate", "Check ATD files: every problem, where it is and how to fix it."),
    "schema": ("atd.cli.validate", "Print the JSON Schema of the ATD model."),
    "translate": ("atd.cli.translate", "Translate an ATD into an ESTD for one robot."),
    "check": ("atd.cli.check", "Which installed robot can do which task, and why not."),
    "run": ("atd.cli.run", "Run a task on a simulated robot: the outcome in the task's terms."),
    "graph": ("atd.cli.graph", "Draw a task's state machine (SVG, PNG or DOT)."),
    "report": ("atd.cli.review", "One HTML page for a recorded run (atd run --record)."),
    "compare": ("atd.cli.review", "Two recorded runs of one task, state by state.")})
@click.version_option(__version__, prog_name="atd")
def main() -> None:
    """Describe a manipulation task once (ATD), translate it for a robot (ESTD), run it in simulation."""
    try:  # a crash inside an engine's C code still says where it happened, never dies silently
        faulthandler.enable()
    except (OSError, ValueError):  # io.UnsupportedOperation: stderr is no file (an embedding, a test runner)
        pass


@main.group(invoke_without_command=True, lazy={
    "list": ("atd.cli.robots_command", "Every installed robot with its arms and capabilities."),
    "show": ("atd.cli.robots_command", "A robot's arms, mapping table, events and configuration."),
    "test": ("atd.cli.robot_test", "Self-test a simulated robot: kinematics, sensors, a grasp."),
    "new": ("atd.cli.robots_new", "Write a new robot as a pip package whose tests pass.")})
@click.option("--format", "fmt", type=click.Choice(["text", "json"]), default="text", show_default=True,
              help="bare `atd robots`: the list as text, or as one JSON document")
@click.pass_context
def robots(ctx: click.Context, fmt: str) -> None:
    """The robots installed through factories (bare `atd robots` lists them)."""
    if ctx.invoked_subcommand is None:
        ctx.invoke(robots.get_command(ctx, "list"), fmt=fmt)
    elif ctx.get_parameter_source("fmt") is not click.core.ParameterSource.DEFAULT:
        usage_error(f"give --format after the sub-command: atd robots {ctx.invoked_subcommand} ... --format {fmt}")


@main.group(lazy={
    "run": ("atd.cli.campaign_run", "Run a campaign's trials, each judged by the simulator."),
    "report": ("atd.cli.campaign_report", "Success rates with Wilson intervals, per group and condition."),
    "export": ("atd.cli.campaign_report", "Every trial of a campaign, every field, for other tools.")})
def campaign() -> None:
    """Trial campaigns: run a task many times under perturbed truth, judge each trial by the simulator."""
