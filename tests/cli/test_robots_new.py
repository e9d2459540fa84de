"""`atd robots new` writes a robot package that runs as generated, with either hand or from a URDF.

docs/writing-a-robot.md's test installs a generated package with `pip install -e` and runs its
own tests (self-test and a pick-and-place in both engines); here both hands' packages are
installed the cheap way, as the .dist-info pip would write beside the package folders."""

from __future__ import annotations

import importlib.metadata
import os
import subprocess
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner

from atd.cli import main
from tests.conftest import EXAMPLES, REPO
from tests.factories.test_urdf import PANDA, URDF
from tests.plugin_site import register_robot

ROBOTS = {"jaws": ["--hand", "parallel_jaw"], "fingers": ["--hand", "multi_finger"], "franka": ["--from-urdf", str(PANDA)]}
# The guide's test runs the parallel-jaw package's own tests: its self-test and pick-and-place in both engines
NOT_IN_THE_GUIDE = ["fingers", "franka"]


@pytest.fixture(scope="module")
def installed(tmp_path_factory) -> dict[str, str]:
    """The environment in which both generated robots are installed."""
    root = tmp_path_factory.mktemp("new")
    for name, options in ROBOTS.items():
        result = CliRunner().invoke(main, ["robots", "new", name, *options, "-o", str(root / name)])
        assert result.exit_code == 0, result.output
        register_robot(root / "site", name, f"atd_{name}.factory:{name.capitalize()}Factory")
    folders = [str(REPO), str(root / "site"), *(str(root / name) for name in ROBOTS)]
    return {**os.environ, "PYTHONPATH": os.pathsep.join(folders)}


def _atd(env: dict[str, str], *args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "atd", *args], env=env, capture_output=True, text=True, timeout=600)


@pytest.mark.parametrize("engine", ["mujoco", "pybullet"])
@pytest.mark.parametrize("robot", NOT_IN_THE_GUIDE)
def test_the_multi_finger_and_the_urdf_robots_pass_the_self_test(installed, robot, engine):
    result = _atd(installed, "robots", "test", robot, "--engine", engine)
    assert result.returncode == 0 and "7/7 checks passed" in result.stdout, result.stdout + result.stderr


@pytest.mark.parametrize("engine", ["mujoco", "pybullet"])
@pytest.mark.parametrize("robot", NOT_IN_THE_GUIDE)
def test_the_multi_finger_and_the_urdf_robots_run_the_pick_and_place_example(installed, robot, engine):
    result = _atd(installed, "run", str(EXAMPLES / "pick_and_place.xml"), "--robot", robot, "--engine", engine)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "outcome: succeeded: reached 'done'" in result.stdout


def test_each_maps_as_its_kind_of_hand(installed):
    jaws, fingers, _ = (_atd(installed, "robots", "show", name).stdout for name in ROBOTS)
    assert "| grasp | grasp | grasp force |" in jaws and "| slide | - |" in jaws
    assert "| grasp | robust_grasp | pregrasp size |" in fingers and "| slide | slide |" in fingers
    assert "grasp_stable: tactile_force_above[on=tactile_f1+tactile_f2+tactile_f3" in fingers  # not the palm


def test_the_urdf_robot_reads_the_installed_urdf_and_stands_where_its_home_is_central(installed):
    folder = Path(installed["PYTHONPATH"].split(os.pathsep)[-1])
    text = (folder / "atd_franka" / "description.py").read_text()
    assert "URDF = Path(str(files('pybullet_data') / 'franka_panda/panda.urdf'))" in text
    assert "FINGERS = ('panda_finger_joint1', 'panda_finger_joint2')" in text and "HAND_ROOT = 'panda_hand'" in text
    assert not list(folder.rglob("*.urdf")) and not list(folder.rglob("*.obj"))  # nothing copied


@pytest.mark.parametrize(("urdf", "options", "code", "message"), [
    ("panda", ["--hand", "multi_finger"], 2, "--from-urdf makes a parallel-jaw robot (--hand parallel_jaw)"),
    ("arm", [], 1, "robot.urdf: found 0 links with two prismatic finger joints"),
    ("broken", [], 1, "robot.urdf:10: joint 'shoulder' is of type 'planar', which atd cannot simulate"),
])
def test_a_urdf_it_cannot_start_from_is_one_line_naming_it(tmp_path, monkeypatch, urdf, options, code, message):
    monkeypatch.chdir(tmp_path)
    path = PANDA
    if urdf != "panda":
        (tmp_path / "meshes").mkdir()
        (tmp_path / "meshes" / "arm.obj").write_text(  # a 10 cm tetrahedron (in mm: the URDF scales it by 0.001)
            "v 0 0 0\nv 100 0 0\nv 0 100 0\nv 0 0 100\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
        path = tmp_path / "robot.urdf"
        path.write_text(URDF.format(kind="revolute" if urdf == "arm" else "planar"))
    result = CliRunner().invoke(main, ["robots", "new", "gizmo", "--from-urdf", str(path), *options])
    assert result.exit_code == code and message in result.output, result.output
    assert len(result.output.strip().splitlines()) == 1 and not (tmp_path / "atd-gizmo").exists()


def test_it_says_what_it_wrote_and_what_to_do_next(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    result = CliRunner().invoke(main, ["robots", "new", "gizmo"])
    assert result.exit_code == 0, result.output
    assert result.output.splitlines() == ["wrote the robot 'gizmo' to atd-gizmo/",
                                          "next: pip install -e atd-gizmo && atd robots test gizmo"]
    written = sorted(str(p.relative_to(tmp_path / "atd-gizmo")) for p in (tmp_path / "atd-gizmo").rglob("*.*"))
    assert written == ["README.md", "atd_gizmo/__init__.py", "atd_gizmo/config.toml", "atd_gizmo/description.py",
                       "atd_gizmo/factory.py", "pyproject.toml", "tests/pick_and_place.xml", "tests/test_gizmo.py"]
    pyproject = (tmp_path / "atd-gizmo" / "pyproject.toml").read_text()
    assert 'gizmo = "atd_gizmo.factory:GizmoFactory"' in pyproject
    assert 'atd_gizmo = ["config.toml"]' in pyproject  # a wheel carries the tuning
    # it depends on this project by the distribution name it is installed as ("atd" on PyPI is another project)
    assert 'dependencies = ["atd-robotics"]' in pyproject and importlib.metadata.distribution("atd-robotics")


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
