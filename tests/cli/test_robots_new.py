"""`atd robots new` writes a robot package that pip installs and that runs as generated."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner

from atd.cli import main
from tests.conftest import EXAMPLES, REPO


@pytest.fixture(scope="module")
def demo(tmp_path_factory) -> tuple[Path, dict[str, str]]:
    """`atd robots new demo` built and installed by pip into a site folder of its own:
    (package folder, environment). docs/writing-a-robot.md's test installs one in place (-e)."""
    root = tmp_path_factory.mktemp("new")
    result = CliRunner().invoke(main, ["robots", "new", "demo", "--hand", "parallel_jaw", "-o", str(root / "demo")])
    assert result.exit_code == 0, result.output
    pip = subprocess.run([sys.executable, "-m", "pip", "install", "-q", "--no-deps", "--target", str(root / "site"),
                          str(root / "demo")], capture_output=True, text=True, timeout=600)
    assert pip.returncode == 0, pip.stderr[-2000:]
    return root / "demo", {**os.environ, "PYTHONPATH": f"{REPO}{os.pathsep}{root / 'site'}"}


def test_a_wheel_of_it_carries_its_config(demo):
    """Installed from a built wheel, not in place: config.toml must travel as package data."""
    folder, env = demo
    shown = subprocess.run([sys.executable, "-m", "atd", "robots", "show", "demo"], env=env, capture_output=True,
                           text=True, timeout=120).stdout
    assert "close_until_force: force_source=tactile, grasp_force=15" in shown
    assert str(folder) not in shown  # the installed copy's description, not the source folder's


@pytest.mark.parametrize("engine", ["mujoco", "pybullet"])
def test_the_generated_robot_runs_the_pick_and_place_example(demo, engine):
    _, env = demo
    result = subprocess.run([sys.executable, "-m", "atd", "run", str(EXAMPLES / "pick_and_place.xml"),
                             "--robot", "demo", "--engine", engine], env=env, capture_output=True, text=True,
                            timeout=600)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "outcome: succeeded: reached 'done'" in result.stdout


def test_it_says_what_it_wrote_and_what_to_do_next(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    result = CliRunner().invoke(main, ["robots", "new", "gizmo"])
    assert result.exit_code == 0, result.output
    assert result.output.splitlines() == ["wrote the robot 'gizmo' to atd-gizmo/",
                                          "next: pip install -e atd-gizmo && atd robots test gizmo"]
    written = sorted(str(p.relative_to(tmp_path / "atd-gizmo")) for p in (tmp_path / "atd-gizmo").rglob("*.*"))
    assert written == ["README.md", "atd_gizmo/__init__.py", "atd_gizmo/config.toml", "atd_gizmo/description.py",
                       "atd_gizmo/factory.py", "pyproject.toml", "tests/pick_and_place.xml", "tests/test_gizmo.py"]
    assert 'gizmo = "atd_gizmo.factory:GizmoFactory"' in (tmp_path / "atd-gizmo" / "pyproject.toml").read_text()


@pytest.mark.parametrize(("args", "message"), [
    (["Gizmo"], "'Gizmo' cannot name a robot: use a lower-case letter"),
    (["melfa"], "a robot 'melfa' is already installed; choose another name"),
    (["gizmo", "-o", "taken"], "taken already exists; give -o a new folder, or remove it first"),
    (["gizmo", "-o", "no/such/gizmo"], "the folder no/such does not exist; create it or give -o elsewhere"),
    (["gizmo", "--hand", "tentacle"], "Invalid value for '--hand': 'tentacle'"),
])
def test_what_it_cannot_write_is_one_line_and_leaves_nothing(tmp_path, monkeypatch, args, message):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "taken").mkdir()
    result = CliRunner().invoke(main, ["robots", "new", *args])
    assert result.exit_code == 2 and message in result.output, result.output
    assert sorted(p.name for p in tmp_path.iterdir()) == ["taken"]
    assert list((tmp_path / "taken").iterdir()) == []
