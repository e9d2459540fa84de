"""PyBullet is an optional install (PyPI has its wheels for CPython 3.11 only): where it is
missing, MuJoCo runs a task, and whatever needs PyBullet (its engine, the library's meshes from
`pybullet_data`) is refused up front with the fix, located, never a traceback. PyBullet is hidden
here the way a Python without it would look: `import pybullet` fails in every process."""

from __future__ import annotations

import os
import subprocess
import sys
from importlib.metadata import requires
from pathlib import Path

import pytest
from packaging.requirements import Requirement

from tests.conftest import EXAMPLES

FIX = "pip install 'atd-robotics[pybullet]'"


@pytest.fixture(scope="module")
def without_pybullet(tmp_path_factory: pytest.TempPathFactory) -> dict[str, str]:
    """An environment whose Python processes (the engine's child process too) cannot import PyBullet."""
    folder = tmp_path_factory.mktemp("no_pybullet")
    (folder / "sitecustomize.py").write_text("import sys\nsys.modules['pybullet'] = sys.modules['pybullet_data'] = None\n")
    return {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [str(folder), os.environ.get("PYTHONPATH")]))}


def atd(env: dict[str, str], *args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "atd", *args], capture_output=True, text=True, timeout=300, env=env)


def test_the_default_install_leaves_pybullet_to_its_extra() -> None:
    [pybullet] = [r for r in map(Requirement, requires("atd-robotics") or []) if r.name == "pybullet"
                  and r.marker.evaluate({"extra": "pybullet"})]
    assert not pybullet.marker.evaluate({"extra": ""})


def test_a_task_runs_in_mujoco_without_pybullet(without_pybullet: dict[str, str]) -> None:
    ran = atd(without_pybullet, "run", str(EXAMPLES / "simple_move.xml"), "--robot", "melfa")
    assert ran.returncode == 0, ran.stderr
    assert "outcome: succeeded" in ran.stdout


def test_the_pybullet_engine_is_refused_with_the_fix(without_pybullet: dict[str, str]) -> None:
    ran = atd(without_pybullet, "run", str(EXAMPLES / "simple_move.xml"), "--robot", "melfa", "--engine", "pybullet")
    assert ran.returncode == 2
    assert FIX in ran.stderr and "Traceback" not in ran.stderr


def test_a_world_with_a_mesh_object_is_a_located_error(without_pybullet: dict[str, str], tmp_path: Path) -> None:
    world = tmp_path / "world.toml"
    world.write_text('[[object]]\nlibrary = "ball"\nposition = [0.1, 0.0]\n\n'
                     '[[object]]\nlibrary = "mug"\nposition = [0.1, 0.2]\n')
    ran = atd(without_pybullet, "run", str(EXAMPLES / "simple_move.xml"), "--robot", "melfa", "--world", str(world))
    assert ran.returncode == 1
    assert f"{world}:6:1: error[WLD026]: library object 'mug'" in ran.stderr
    assert "ball" not in ran.stderr.split("error[WLD026]")[0] and FIX in ran.stderr and "Traceback" not in ran.stderr


def test_a_campaign_asking_for_pybullet_is_refused_before_any_trial(without_pybullet: dict[str, str],
                                                                    tmp_path: Path) -> None:
    spec = tmp_path / "spec.toml"
    spec.write_text(f'name = "c"\ntasks = ["{EXAMPLES / "grasp_and_lift.xml"}"]\nrobots = ["melfa"]\n'
                    'engines = ["mujoco", "pybullet"]\nobjects = ["ball", "duck"]\n')
    ran = atd(without_pybullet, "campaign", "run", str(spec), "--store", str(tmp_path / "c.sqlite"))
    assert ran.returncode == 1
    assert f"{spec}:4:1: error[CMP029]: the pybullet engine" in ran.stderr
    assert f"{spec}:5:1: error[CMP029]: library object 'duck'" in ran.stderr
    assert not (tmp_path / "c.sqlite").exists()
