"""Shared test helpers: write a small ATD to a temp dir and read back its diagnostics.

The whole suite runs with a fourth robot installed beside the built-ins: the Panda of
plugins/panda, which the test extras install (`pip install -e '.[test]'`).
"""

from __future__ import annotations

import textwrap
from pathlib import Path
from typing import Callable

import pytest

from atd.model import Diagnostic, load_task

REPO = Path(__file__).resolve().parents[1]
EXAMPLES = REPO / "examples"
# A box the robot knows the object in, walls as obstacles: the translation checks of issue 12
KNOWN_BOX = REPO / "tests" / "data" / "known_box"
SEEDS = REPO / "tests" / "data" / "seeds"


@pytest.fixture
def atd_file(tmp_path: Path) -> Callable[..., Path]:
    """Write dedented XML to a file in tmp_path; returns its path."""

    def write(xml: str, name: str = "task.xml") -> Path:
        path = tmp_path / name
        path.write_text(textwrap.dedent(xml).lstrip())
        return path

    return write


@pytest.fixture
def diagnose(atd_file) -> Callable[..., list[Diagnostic]]:
    """Validate XML text; returns its diagnostics."""

    def run(xml: str, name: str = "task.xml") -> list[Diagnostic]:
        return load_task(atd_file(xml, name))[1]

    return run
