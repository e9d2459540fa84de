"""`atd robots new NAME`: write a robot package that installs and runs as generated."""

from __future__ import annotations

from pathlib import Path

import click

from atd.cli.app import EXIT_INVALID, robots, usage_error
from atd.scaffold import HANDS, ScaffoldError, UrdfScaffoldError, check_name, package_files, write_package
from factories.registry import installed


@robots.command("new")
@click.argument("name")
@click.option("--hand", type=click.Choice(HANDS), default=HANDS[0], show_default=True,
              help="The kind of hand the robot starts with.")
@click.option("--from-urdf", "urdf", type=click.Path(exists=True, dir_okay=False, path_type=Path), default=None,
              help="Read the arm and gripper from this URDF (and its meshes) instead of starting from a generic arm.")
@click.option("-o", "--output", type=click.Path(path_type=Path), default=None,
              help="The package folder to create (default: ./atd-NAME).")
def new(name: str, hand: str, urdf: Path | None, output: Path | None) -> None:
    """Write the robot NAME as a pip package: pyproject.toml (the `atd.factories` entry point),
    description, factory, config.toml and tests, which pass as generated.

    Then: pip install -e DIR && atd robots test NAME
    """
    target = output if output is not None else Path(f"atd-{name}")
    try:
        check_name(name, list(installed()))
        write_package(target, package_files(name, hand, urdf))
    except UrdfScaffoldError as exc:  # the URDF is invalid input: exit 1, as a task with errors is
        click.echo(f"error: {exc}", err=True)
        raise SystemExit(EXIT_INVALID) from None
    except ScaffoldError as exc:
        usage_error(str(exc))
    click.echo(f"wrote the robot '{name}' to {target}/")
    click.echo(f"next: pip install -e {target} && atd robots test {name}")
