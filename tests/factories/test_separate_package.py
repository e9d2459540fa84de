"""A robot from another installed package is a robot like the built-ins: its own config and
description are used, shown where they are, and the suite's robot lists follow what is installed."""

from __future__ import annotations

import os
import subprocess
import sys

from click.testing import CliRunner

from atd.cli import main
from factories.registry import create
from tests.conftest import REPO
from tests.plugin_site import write_robot_package

# Each test installs its robot under a name of its own: Python keeps a package imported once.


def test_its_config_toml_is_used(tmp_path, monkeypatch):
    write_robot_package(tmp_path, "twin", "[twin.controllers.close_until_force]\ngrasp_force = 33.0\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    assert create("twin").config.controllers["close_until_force"]["grasp_force"] == 33.0
    shown = CliRunner().invoke(main, ["robots", "show", "twin"]).output
    assert "close_until_force: " in shown and "grasp_force=33" in shown


def test_show_names_its_own_description_file(tmp_path, monkeypatch):
    package = write_robot_package(tmp_path, "shown")
    monkeypatch.syspath_prepend(str(tmp_path))
    result = CliRunner().invoke(main, ["robots", "show", "shown"])
    assert result.exit_code == 0, result.output
    assert f"reach is checked on {package.resolve() / 'description.py'}: by inverse kinematics" in result.output
    assert "factories/shown" not in result.output


def test_tests_about_the_installed_robots_pass_with_another_robot_installed(tmp_path):
    write_robot_package(tmp_path, "twin")
    env = {**os.environ, "PYTHONPATH": f"{REPO}{os.pathsep}{tmp_path}"}
    selected = ["tests/sim/test_robots_test_cli.py::test_the_three_robots_and_both_tombatossals_hands_are_there",
                "tests/sim/test_robots_test_cli.py::test_unknown_robot_is_named_with_the_known_ones",
                "tests/cli/test_translate_cli.py::test_unknown_robot_and_arm_are_usage_errors"]
    result = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
                             f"--basetemp={tmp_path / 'inner'}", *selected],
                            cwd=REPO, env=env, capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stdout[-3000:]
    assert "3 passed" in result.stdout
    listed = subprocess.run([sys.executable, "-m", "atd", "robots", "list"], cwd=REPO, env=env,
                            capture_output=True, text=True, timeout=120)
    assert "twin: a Melfa twin from another package" in listed.stdout
