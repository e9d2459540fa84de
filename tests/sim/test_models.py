"""One description, two models: the MJCF and the URDF say the same, in Menagerie's style."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest
from lxml import etree

from atd.sim import load_description, variants
from atd.sim.models import mjcf, urdf
from atd.sim.mujoco_engine import compile_mjcf
from atd.sim.scene import box_scene
from primitives.robot import HandMode


@pytest.mark.parametrize(("robot", "arm"), variants())
def test_mjcf_and_urdf_have_the_same_joints_axes_and_limits(robot, arm) -> None:
    d = load_description(robot, arm)
    model = compile_mjcf(mjcf(d, box_scene()), d)
    tree = etree.fromstring(urdf(d).encode())
    moving = {j.get("name"): j for j in tree.iter("joint") if j.get("type") != "fixed"}
    assert set(moving) == set(d.joints)
    for name, joint in d.joints.items():
        urdf_joint = moving[name]
        limit = urdf_joint.find("limit")
        assert (float(limit.get("lower")), float(limit.get("upper"))) == (joint.lower, joint.upper)
        assert tuple(float(v) for v in urdf_joint.find("axis").get("xyz").split()) == joint.axis
        j = model.joint(name)
        np.testing.assert_allclose(j.range, (joint.lower, joint.upper))
        np.testing.assert_allclose(model.jnt_axis[j.id], joint.axis)


def test_mujoco_model_follows_menagerie_conventions(melfa) -> None:
    model = compile_mjcf(mjcf(melfa, box_scene()), melfa)
    groups = {int(g) for g in model.geom_group}
    assert {2, 3} <= groups  # visual and collision geoms apart
    visual = model.geom_group == 2
    assert not model.geom_contype[visual].any() and not model.geom_conaffinity[visual].any()
    assert model.site("attachment_site").id >= 0
    key = model.key("home")
    arm = [model.joint(n).qposadr[0] for n in melfa.arm_joints]
    np.testing.assert_allclose(key.qpos[arm], melfa.home)
    assert model.opt.cone == mujoco.mjtCone.mjCONE_ELLIPTIC and model.opt.impratio == 100
    assert model.opt.integrator == mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    pads = [model.geom(p.name).id for p in melfa.hand.pads]
    assert all(model.geom_condim[g] == 4 for g in pads)


def test_robot_geoms_touch_the_world_but_not_each_other(melfa) -> None:
    model = compile_mjcf(mjcf(melfa, box_scene()), melfa)
    robot = [g for g in range(model.ngeom) if model.geom_group[g] == 3]
    table = model.geom("table").id
    for g in robot:
        assert model.geom_contype[g] & model.geom_conaffinity[table]
        assert not model.geom_contype[g] & model.geom_conaffinity[g]


def test_links_have_plausible_masses_and_positive_inertias() -> None:
    for robot, arm in variants():
        d = load_description(robot, arm)
        for link in d.links:
            assert link.mass > 0, link.name
            assert min(link.inertia_diagonal) > 0, link.name
        assert 0.3 < d.hand_mass < 2.5, d.label  # grippers of 0.4 kg to an SDH2 of about 2 kg


def test_a_urdf_robots_collision_meshes_stand_where_its_description_puts_them_in_both_models() -> None:
    d = load_description("panda", None)  # every link collides as its mesh from pybullet_data
    model = compile_mjcf(mjcf(d, box_scene()), d)
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key("home").id)
    mujoco.mj_forward(model, data)
    poses = d.link_poses({model.joint(j).name: data.qpos[model.jnt_qposadr[j]] for j in range(model.njnt)
                          if model.joint(j).name in d.joints})
    tree = etree.fromstring(urdf(d).encode())
    for link in d.links:
        (shape,) = link.shapes
        assert shape.kind == "mesh"
        geom = model.geom(f"{link.name}_0")
        assert model.geom_type[geom.id] == mujoco.mjtGeom.mjGEOM_MESH
        assert model.geom_contype[geom.id] and not model.geom_conaffinity[geom.id]  # touches the world, not itself
        mesh = model.geom_dataid[geom.id]  # MuJoCo keeps the vertices about the mesh's centroid: place them
        start, count = model.mesh_vertadr[mesh], model.mesh_vertnum[mesh]
        world = model.mesh_vert[start:start + count] @ data.geom_xmat[geom.id].reshape(3, 3).T + data.geom_xpos[geom.id]
        for axis in np.vstack([np.eye(3), -np.eye(3)]):
            assert (world @ axis).max() == pytest.approx(shape.support(poses[link.name], axis), abs=1e-6)
        (collision,) = tree.find(f"link[@name='{link.name}']").iter("collision")
        assert collision.find("geometry/mesh").get("filename") == str(shape.mesh)


@pytest.mark.parametrize(("robot", "coupled"), [("melfa", ("pg70_left_jaw", "pg70_right_jaw")),
                                               ("baxter", ("gripper_left_jaw", "gripper_right_jaw"))])
def test_a_grippers_jaws_move_as_one_in_both_models(robot, coupled, engine, robot_of) -> None:
    """A gripper's two jaws on one spindle: pushed aside by a held object, one jaw cannot
    give way while the other follows it in (see `Hand.couplings`)."""
    d = load_description(robot, "right" if robot == "baxter" else None)
    assert [(a, b) for a, b, _ in d.hand.couplings] == [coupled]
    sim = robot_of(d, engine, box_scene())
    sim.command_hand(np.zeros(len(d.hand.dofs)), HandMode.FORCE)  # no motor holds them
    first, second = coupled
    sim._set_joints({first: 0.5 * d.joints[first].upper, second: 0.0})  # one joint alone, as a push would
    for _ in range(100):
        sim.step()
    q = dict(zip([*d.arm_joints, *sim.hand_joints], sim._joint_state()[0]))
    assert q[first] == pytest.approx(q[second], abs=1e-3)
