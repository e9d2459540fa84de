"""Each command's module is imported when the command is used: every command the groups
name is there, and `atd validate` starts without loading the engines or the campaign tools."""

from __future__ import annotations

import subprocess
import sys

import click
import pytest

from atd.cli import main
from tests.conftest import EXAMPLES


def _groups(group: click.Group, ctx: click.Context):
    yield group
    for name in group.list_commands(ctx):
        command = group.get_command(ctx, name)
        if isinstance(command, click.Group):
            yield from _groups(command, ctx)


def test_every_command_a_group_names_is_registered_by_its_module():
    ctx = click.Context(main)
    for group in _groups(main, ctx):
        for name in group.list_commands(ctx):
            command = group.get_command(ctx, name)
            assert command is not None and command.name == name, (group.name, name)


def test_validate_loads_no_engine_and_no_campaign_tool():
    probe = ("import sys\nfrom atd.cli import main\n"
             "try:\n    main(['validate', sys.argv[1]])\nexcept SystemExit as done:\n    assert done.code == 0, done.code\n"
             "print(sorted(m for m in ('mujoco', 'pybullet', 'atd.runtime', 'atd.campaign', 'matplotlib') "
             "if m in sys.modules))")
    result = subprocess.run([sys.executable, "-c", probe, str(EXAMPLES / "pick_and_place.xml")],
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert result.stdout.splitlines()[-1] == "[]"


def _help_loads(args: list[str]) -> tuple[str, list[str]]:
    """What `atd ARGS --help` prints, and which heavy packages it imported doing so."""
    probe = ("import sys\nfrom atd.cli import main\n"
             "try:\n    main(sys.argv[1:])\nexcept SystemExit as done:\n    assert done.code == 0, done.code\n"
             "print(sorted(m for m in ('mujoco', 'pybullet', 'matplotlib', 'numpy', 'pydantic', 'lxml', 'atd.model', "
             "'atd.runtime', 'atd.campaign', 'atd.sim') if m in sys.modules))")
    result = subprocess.run([sys.executable, "-c", probe, *args, "--help"], capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    *shown, loaded = result.stdout.splitlines()
    return "\n".join(shown), loaded


@pytest.mark.parametrize("group", [[], ["robots"], ["campaign"]])
def test_help_lists_every_command_and_loads_neither_engines_nor_plots(group):
    shown, loaded = _help_loads(group)
    assert loaded == "[]"
    command = main if not group else main.commands[group[0]]
    for name, (_, line) in command.lazy.items():
        assert f"  {name} " in shown and line in shown, name

