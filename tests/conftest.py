"""Shared test helpers: write a small ATD to a temp dir and read back its diagnostics.

The whole suite runs with a fourth robot installed beside the built-ins: the Panda of
plugins/atd-panda, registered the way pip would (its folder on the path, its entry point
in a .dist-info), here and in every `atd` the tests start. Extras cannot name a package by
a relative path, so the test extras cannot install it; `pip install -e plugins/atd-panda` does.
"""

from __future__ import annotations

import atexit
import os
import shutil
import sys
import tempfile
import textwrap
from pathlib import Path
from typing import Callable

import pytest

from atd.model import Diagnostic, load_task
from tests.plugin_site import register_robot

REPO = Path(__file__).resolve().parents[1]
EXAMPLES = REPO / "examples"
SEEDS = REPO / "tests" / "data" / "seeds"
PANDA_PACKAGE = REPO / "plugins" / "atd-panda"


def _install_the_panda() -> None:
    site = Path(tempfile.mkdtemp(prefix="atd-panda-site-"))
    atexit.register(shutil.rmtree, site, True)
    register_robot(site, "panda", "atd_panda.factory:PandaFactory")
    folders = [str(PANDA_PACKAGE), str(site)]
    sys.path[:0] = folders
    os.environ["PYTHONPATH"] = os.pathsep.join([*folders, *filter(None, [os.environ.get("PYTHONPATH")])])


_install_the_panda()


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
