"""Every command the README shows works as shown: the Quick start's second command is what CI
runs, the first ends in the flagship demo, and each `$ atd ...` line of its console blocks exits 0
from a folder holding the examples, as a newcomer would type them."""

from __future__ import annotations

import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
README = (REPO / "README.md").read_text()
ATD = [sys.executable, "-m", "atd"]


def _block(lang: str) -> list[str]:
    return [line for block in re.findall(rf"```{lang}\n(.*?)```", README, re.S) for line in block.splitlines()]


def test_the_readme_is_short_and_its_quick_start_is_two_commands_ci_runs_one_of() -> None:
    assert len(README.splitlines()) < 150
    install_and_demo, install_and_test = _block("sh")
    assert install_and_test in (REPO / ".ci" / "run").read_text()
    assert install_and_demo.endswith(".venv/bin/atd run examples/pick_and_place.xml --robot melfa")


COMMANDS = [line.removeprefix("$ atd ") for line in _block("console") if line.startswith("$ atd ")]


def test_the_readme_shows_what_a_newcomer_needs() -> None:
    shown = " ".join(COMMANDS)
    for verb in ("validate", "translate", "run", "--record", "report", "campaign run", "campaign report"):
        assert verb in shown


@pytest.fixture(scope="module")
def folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A user's folder with the examples in it; commands run in order, as in the README."""
    where = tmp_path_factory.mktemp("readme")
    (where / "examples").symlink_to(REPO / "examples")
    return where


@pytest.mark.parametrize("command", ["run examples/pick_and_place.xml --robot melfa", *COMMANDS])
def test_a_readme_command_works_as_shown(command: str, folder: Path) -> None:
    done = subprocess.run([*ATD, *shlex.split(command)], cwd=folder, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    assert "Traceback" not in done.stderr
