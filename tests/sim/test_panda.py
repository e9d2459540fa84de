"""The fourth robot, the Franka Emika Panda of plugins/panda (made from pybullet_data's
URDF by `atd robots new --from-urdf`), runs the examples to success in both engines."""

from __future__ import annotations

import pytest
from click.testing import CliRunner

from atd.cli import main
from atd.sim import load_description
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


def test_the_pandas_arm_weighs_as_identified_and_collides_as_its_meshes():
    d = load_description("panda", None)
    arm = [d.links_by_name[f"panda_link{i}"] for i in range(1, 8)]
    assert sum(link.mass for link in arm) == pytest.approx(16.062, abs=0.001)  # Gaz et al. 2019, not the URDF's 14.05
    assert arm[1].com == (-3.141e-03, -2.872e-02, 3.495e-03) and arm[1].inertia_products[0] == pytest.approx(-3.925e-3)
    assert all(shape.kind == "mesh" and shape.mesh.is_file() for link in d.links for shape in link.shapes)
