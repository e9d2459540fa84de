"""The fourth robot, the Franka Emika Panda of plugins/panda (made from pybullet_data's
URDF by `atd robots new --from-urdf`), runs the examples to success in both engines."""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np
import pybullet as pb
import pybullet_data
import pytest
from click.testing import CliRunner

from atd.cli import main
from atd.model.meshcheck import read_mesh
from atd.sim import load_description
from tests.conftest import EXAMPLES, KNOWN_BOX

MESHES = Path(pybullet_data.getDataPath()) / "franka_panda" / "meshes"


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


def test_the_pandas_arm_and_hand_weigh_as_published_and_collide_as_their_meshes():
    d = load_description("panda", None)
    arm = [d.links_by_name[f"panda_link{i}"] for i in range(1, 8)]
    assert sum(link.mass for link in arm) == pytest.approx(16.062, abs=0.001)  # Gaz et al. 2019, not the URDF's 14.05
    assert arm[1].com == (-3.141e-03, -2.872e-02, 3.495e-03) and arm[1].inertia_products[0] == pytest.approx(-3.925e-3)
    assert all(shape.kind == "mesh" and shape.mesh.is_file() for link in d.links for shape in link.shapes)
    hand = d.links_by_name["panda_hand"]  # Franka's 0.73 kg hand, not the URDF's 0.81 kg at 0.1 kg m^2
    assert (hand.mass, hand.com, hand.inertia) == (0.73, (-0.01, 0.0, 0.03), (1.0e-3, 2.5e-3, 1.7e-3))
    assert d.hand_mass == pytest.approx(0.76)  # with two 15 g fingers


def test_mujoco_draws_the_pandas_visual_meshes_whole_and_collides_its_collision_meshes(robot_of):
    d = load_description("panda", None)
    m = robot_of(d, "mujoco").model
    body = {link.name: mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, link.name) for link in d.links}
    mesh = m.geom_type == mujoco.mjtGeom.mjGEOM_MESH
    drawn = mesh & (m.geom_contype == 0) & (m.geom_conaffinity == 0) & (m.geom_group == 2)
    (hand,) = np.flatnonzero(drawn & (m.geom_bodyid == body["panda_hand"]))
    vertices, faces = read_mesh(MESHES / "visual" / "hand.obj")
    # all five objects of the file: MuJoCo reading the OBJ itself keeps the first only (42 triangles)
    assert m.mesh_facenum[m.geom_dataid[hand]] == len(faces) == 7078
    collided = {mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_GEOM, g) for g in np.flatnonzero(mesh & (m.geom_contype == 1))}
    assert collided == {f"{link.name}_0" for link in d.links}  # one collision mesh a link, as the URDF's
    assert [m.body_mass[body[link.name]] for link in d.links] == pytest.approx([link.mass for link in d.links])


def test_pybullet_draws_the_pandas_visual_meshes_and_collides_its_collision_meshes(robot_of):
    d = load_description("panda", None)
    robot = robot_of(d, "pybullet")
    client, hand = robot.client, robot._index["link:panda_hand"]
    drawn = {v[1]: Path(v[4].decode()) for v in pb.getVisualShapeData(robot.body, physicsClientId=client)}
    assert drawn[hand] == MESHES / "visual" / "hand.obj"
    assert drawn[-1] == MESHES / "collision" / "link0.obj"  # the URDF draws the base as its collision mesh
    (collision,) = pb.getCollisionShapeData(robot.body, hand, physicsClientId=client)
    assert Path(collision[4].decode()) == MESHES / "collision" / "hand.obj"


def test_the_panda_is_refused_the_walled_box_by_the_margin_not_by_its_walls(tmp_path):
    d = load_description("panda", None)
    walls = [((0.10, -0.16, 0.03), (0.16, 0.01, 0.06)), ((0.10, 0.0, 0.03), (0.16, 0.01, 0.06))]  # empty_the_box.xml
    tcp = np.eye(4)
    tcp[:3, :3], tcp[:3, 3] = np.diag([-1.0, 1.0, -1.0]), (0.10, -0.08, 0.025)  # hand down, at the cube's centre
    assert d.hand_in_boxes("open", tcp, walls) == {}  # the 20 cm housing passes over the walls, the fingers inside
    grown = [(centre, tuple(v + 0.02 for v in size)) for centre, size in walls]  # 1 cm all round
    assert d.hand_in_boxes("open", tcp, grown) == {0: ["panda_hand", "panda_rightfinger"],
                                                    1: ["panda_hand", "panda_leftfinger"]}
    result = CliRunner().invoke(main, ["translate", str(KNOWN_BOX / "empty_the_box.xml"), "--robot", "panda",
                                       "-o", str(tmp_path / "box.estd.xml")])
    assert result.exit_code == 4 and "with its panda_hand, panda_leftfinger and panda_rightfinger" in result.output
