"""The root click group and the exit codes every sub-command shares."""

import faulthandler
import importlib
from pathlib import Path
from typing import Iterable, Mapping, NoReturn

import click

from atd import __version__
from atd.model import ranges
from atd.model.files import OutputError, output_problem, output_problems, write_output

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


def usage_error(message: str) -> NoReturn:
    """One line on stderr and exit 2: the command line asked for something that cannot be done."""
    click.echo(f"error: {message}", err=True)
    raise SystemExit(EXIT_USAGE)


def guard_outputs(outputs: Mapping[str, Path | None], inputs: Iterable[Path] = ()) -> None:
    """Exit 2 before any work when an output would overwrite an input, another output or
    something that is not a regular file."""
    problems = output_problems(outputs, inputs)
    if problems:
        usage_error("; ".join(problems))


def write_or_exit(path: Path, data: bytes) -> None:
    """Write an output atomically, or exit 2 with one line and nothing left behind."""
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

    A command's module is imported when the command is asked for, not at start-up:
    `atd validate` then loads neither the engines nor the campaign tools.
    """

    command_class = GuardedCommand

    def __init__(self, *args, modules: Mapping[str, str] | None = None, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self.modules = dict(modules or {})  # command name -> the module that registers it here

    def list_commands(self, ctx: click.Context) -> list[str]:
        return sorted({*self.commands, *self.modules})

    def get_command(self, ctx: click.Context, name: str) -> click.Command | None:
        if name not in self.commands and name in self.modules:
            importlib.import_module(self.modules[name])
        return super().get_command(ctx, name)


Commands.group_class = Commands


@click.group(cls=Commands, context_settings={"help_option_names": ["-h", "--help"]}, modules={
    "validate": "atd.cli.validate", "schema": "atd.cli.validate", "translate": "atd.cli.translate",
    "check": "atd.cli.check", "run": "atd.cli.run", "graph": "atd.cli.graph", "report": "atd.cli.review",
    "compare": "atd.cli.review"})
@click.version_option(__version__, prog_name="atd")
def main() -> None:
    """Describe a manipulation task once (ATD), translate it for a robot (ESTD), run it in simulation."""
    try:  # a crash inside an engine's C code still says where it happened, never dies silently
        faulthandler.enable()
    except (OSError, ValueError):  # io.UnsupportedOperation: stderr is no file (an embedding, a test runner)
        pass


@main.group(invoke_without_command=True, modules={
    "list": "atd.cli.robots_command", "show": "atd.cli.robots_command", "test": "atd.cli.robot_test",
    "new": "atd.cli.robots_new"})
@click.pass_context
def robots(ctx: click.Context) -> None:
    """The robots installed through factories (bare `atd robots` lists them)."""
    if ctx.invoked_subcommand is None:
        ctx.invoke(robots.get_command(ctx, "list"))


@main.group(modules={"run": "atd.cli.campaign_run", "report": "atd.cli.campaign_report",
                     "export": "atd.cli.campaign_report"})
def campaign() -> None:
    """Trial campaigns: run a task many times under perturbed truth, judge each trial by the simulator."""
