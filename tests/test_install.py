"""`pip install -e '.[test]'` from a clone installs the Panda of plugins/panda beside the
built-in robots; a plain `pip install -e .` does not."""

from __future__ import annotations

import subprocess
import sys
from importlib.metadata import distribution, requires
from pathlib import Path

from packaging.requirements import Requirement

from tests.conftest import REPO


def test_only_the_test_extra_names_this_clones_panda_package():
    [panda] = [r for r in map(Requirement, requires("atd-robotics") or []) if r.name == "atd-panda"]
    assert panda.url == (REPO / "plugins" / "panda").as_uri()
    assert panda.marker.evaluate({"extra": "test"})
    assert not panda.marker.evaluate({"extra": ""})


def test_the_panda_is_installed_as_a_package_and_listed():
    assert distribution("atd-panda").entry_points.select(group="atd.factories", name="panda")
    listed = subprocess.run([sys.executable, "-m", "atd", "robots", "list"], capture_output=True, text=True, timeout=120)
    assert listed.returncode == 0, listed.stderr
    assert any(line.startswith("panda: Franka Emika Panda") for line in listed.stdout.splitlines())


def test_the_installed_panda_is_this_clones_code():
    """pip caches a wheel built from a folder named like name-version (`atd-panda`) and reuses it
    for the same path: a clone at a fixed path then ran a stale Panda. plugins/panda is not cached."""
    import atd_panda.description

    installed = Path(atd_panda.description.__file__).read_text()
    assert installed == (REPO / "plugins" / "panda" / "atd_panda" / "description.py").read_text()
