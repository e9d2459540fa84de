"""The fourth robot, the Franka Emika Panda of plugins/atd-panda (made from pybullet_data's
URDF by `atd robots new --from-urdf`), runs the examples to success in both engines."""

from __future__ import annotations

import pytest
from click.testing import CliRunner

from atd.cli import main
from tests.conftest import EXAMPLES


@pytest.mark.parametrize("task", ["pick_and_place", "grasp_and_lift", "push_object"])
def test_the_panda_runs_the_example_to_success(task, engine):
    result = CliRunner().invoke(main, ["run", str(EXAMPLES / f"{task}.xml"), "--robot", "panda", "--engine", engine])
    assert result.exit_code == 0, result.output
    assert "outcome: succeeded" in result.output


def test_atd_check_shows_the_panda_doing_the_examples():
    tasks = [str(EXAMPLES / f"{task}.xml") for task in ("pick_and_place", "grasp_and_lift", "push_object")]
    result = CliRunner().invoke(main, ["check", *tasks])
    assert result.exit_code == 0, result.output
    assert "panda" in result.output.splitlines()[0]
