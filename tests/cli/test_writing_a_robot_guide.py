"""Every console command of docs/writing-a-robot.md runs as written, in order, in a fresh
folder beside a copy of the examples, and prints the lines the guide shows after it.

`pip install -e` installs into a virtual environment made for the test on top of the one
running it (a .pth adds the running one's site-packages), so the suite's own stays as it was."""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

from tests.conftest import EXAMPLES, REPO

GUIDE = REPO / "docs" / "writing-a-robot.md"


def console_steps(markdown: str) -> list[tuple[str, list[str]]]:
    """(command, lines the guide shows it printing) for every `$ ` line of its console blocks."""
    steps: list[tuple[str, list[str]]] = []
    for block in re.findall(r"```console\n(.*?)```", markdown, re.S):
        for line in block.splitlines():
            if line.startswith("$ "):
                steps.append((line[2:], []))
            elif line.strip():
                steps[-1][1].append(line.strip())
    return steps


def _layered_venv(folder: Path) -> Path:
    """A venv whose Python also sees the running one's packages; returns its python."""
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(folder)], check=True, timeout=120)
    python = folder / "bin" / "python"
    own = subprocess.run([str(python), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                         capture_output=True, text=True, check=True).stdout.strip()
    (Path(own) / "_running_env.pth").write_text(
        f"import site; site.addsitedir({sysconfig.get_paths()['purelib']!r})\n")
    return python


def test_every_command_of_the_guide_runs_and_prints_what_it_shows(tmp_path):
    steps = console_steps(GUIDE.read_text())
    assert [c.split()[0] for c, _ in steps][:2] == ["atd", "pip"]  # it starts from nothing
    shutil.copytree(EXAMPLES, tmp_path / "examples")
    python = _layered_venv(tmp_path / "venv")
    programs = {"atd": [str(python), "-m", "atd"], "pip": [str(python), "-m", "pip"], "python": [str(python)]}
    for command, shown in steps:
        program, *args = command.split()
        result = subprocess.run(programs[program] + args, cwd=tmp_path, capture_output=True, text=True,
                                timeout=900)
        assert result.returncode == 0, f"$ {command}\n{result.stdout[-2000:]}\n{result.stderr[-2000:]}"
        for line in shown:
            assert line in result.stdout, f"$ {command} did not print {line!r}:\n{result.stdout[-2000:]}"
