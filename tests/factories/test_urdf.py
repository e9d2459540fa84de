"""A URDF becomes description links; what cannot be imported is named at its file:line."""

from __future__ import annotations

import textwrap
from pathlib import Path

import numpy as np
import pybullet_data
import pytest

from factories.urdf import UrdfError, read_urdf

PANDA = Path(pybullet_data.getDataPath()) / "franka_panda" / "panda.urdf"


def test_the_pandas_urdf_gives_its_tree_limits_masses_and_collision_meshes():
    model = read_urdf(PANDA)
    assert [link.name for link in model.links][:3] == ["panda_link0", "panda_link1", "panda_link2"]
    joints = {link.joint.name: link.joint for link in model.links if link.joint}
    assert len(joints) == 9  # seven arm joints and the two fingers; the fixed ones weld
    assert joints["panda_joint4"].lower == pytest.approx(-3.1416) and joints["panda_joint4"].upper == 0.0
    assert joints["panda_joint1"].effort == 87.0 and joints["panda_joint7"].velocity == pytest.approx(2.61)
    assert joints["panda_finger_joint2"].kind == "prismatic" and joints["panda_finger_joint2"].axis == (0, -1, 0)
    hand = model.link("panda_hand")  # panda_link8 and panda_grasptarget are bare frames, folded away
    assert "panda_link8" not in [link.name for link in model.links] and len(model.links) == 11
    assert hand.parent == "panda_link7" and hand.joint is None and hand.mass == pytest.approx(0.81)
    assert hand.origin.xyz == pytest.approx((0, 0, 0.107)) and hand.origin.rpy == pytest.approx((0, 0, -0.785398))
    assert hand.com == (0, 0, 0.04) and hand.inertia == (0.1, 0.1, 0.1)
    (mesh,) = hand.shapes  # the collision mesh itself, read from the installed pybullet_data
    assert mesh.kind == "mesh" and mesh.mesh == PANDA.parent / "meshes" / "collision" / "hand.obj"
    low, high = mesh.bounds()  # the hand is about 20 cm across its fingers' travel
    assert max(high - low) == pytest.approx(0.204, abs=0.002)
    # the right finger's mesh is turned half round about z: it lies on the other side
    left, right = (model.link(f"panda_{side}finger").shapes[0] for side in ("left", "right"))
    assert right.bounds()[0][1] == pytest.approx(-left.bounds()[1][1])


def test_a_collision_mesh_is_read_at_its_scale_with_the_inertias_products(tmp_path):
    urdf = URDF.format(kind="revolute").replace(
        '<cylinder radius="0.03" length="0.2"/>', '<mesh filename="meshes/arm.obj" scale="0.001 0.001 0.001"/>')
    urdf = urdf.replace('<inertia ixx="0.01" iyy="0.02" izz="0.03"/>',  # a body's: principal moments A + B >= C
                        '<inertia ixx="0.02" iyy="0.03" izz="0.04" ixy="0.001" ixz="-0.002" iyz="0.003"/>')
    arm = read_urdf(_write(tmp_path, urdf)).links[1]
    (shape,) = arm.shapes
    assert shape.kind == "mesh" and shape.origin.xyz == (0, 0, 0.1)
    assert np.ptp(shape.points, axis=0) == pytest.approx((0.1, 0.2, 0.3))  # drawn in millimetres
    assert arm.inertia == (0.02, 0.03, 0.04) and arm.inertia_products == (0.001, -0.002, 0.003)


URDF = """\
<robot name="two">
  <link name="base">
    <collision><geometry><box size="0.2 0.2 0.1"/></geometry></collision>
  </link>
  <link name="arm">
    <inertial><origin xyz="0 0 0.1"/><mass value="1.5"/><inertia ixx="0.01" iyy="0.02" izz="0.03"/></inertial>
    <collision><origin xyz="0 0 0.1"/><geometry><cylinder radius="0.03" length="0.2"/></geometry></collision>
    <visual><geometry><mesh filename="package://meshes/arm.obj" scale="0.001 0.001 0.001"/></geometry></visual>
  </link>
  <joint name="shoulder" type="{kind}">
    <parent link="base"/><child link="arm"/>
    <origin xyz="0 0 0.1" rpy="0 0 1.5708"/><axis xyz="0 0 2"/>
    <limit effort="10" velocity="1" lower="-1" upper="1"/><dynamics damping="0.5" friction="0.1"/>
  </joint>
</robot>
"""


# A 100 x 200 x 300 mm box, drawn in millimetres as many CAD exports are.
ARM_MM = "".join(f"v {x} {y} {z}\n" for x in (0, 100) for y in (0, 200) for z in (0, 300)) + \
    "f 1 2 4 3\nf 5 7 8 6\nf 1 5 6 2\nf 3 4 8 7\nf 1 3 7 5\nf 2 6 8 4\n"


def _write(tmp_path: Path, text: str, mesh: bool = True) -> Path:
    if mesh:
        (tmp_path / "meshes").mkdir(exist_ok=True)
        (tmp_path / "meshes" / "arm.obj").write_text(ARM_MM)
    path = tmp_path / "robot.urdf"
    path.write_text(textwrap.dedent(text))
    return path


def test_primitives_joints_and_dynamics_are_taken_as_written(tmp_path):
    model = read_urdf(_write(tmp_path, URDF.format(kind="revolute")))
    base, arm = model.links
    assert base.shapes[0].size == pytest.approx((0.1, 0.1, 0.05))
    assert arm.shapes[0].kind == "cylinder" and arm.shapes[0].size == pytest.approx((0.03, 0.1))
    assert arm.origin.rpy == (0, 0, 1.5708) and arm.mass == 1.5 and arm.inertia == (0.01, 0.02, 0.03)
    joint = arm.joint
    assert joint.axis == (0, 0, 1) and (joint.damping, joint.friction) == (0.5, 0.1)
    assert joint.servo.kp > 0 and joint.servo.kv > 0


def test_a_continuous_joint_turns_two_full_turns_either_way(tmp_path):
    joint = read_urdf(_write(tmp_path, URDF.format(kind="continuous"))).links[1].joint
    assert (joint.lower, joint.upper) == pytest.approx((-2 * np.pi, 2 * np.pi))


@pytest.mark.parametrize(("edit", "message"), [
    (lambda t: t.format(kind="floating"),
     ":10: joint 'shoulder' is of type 'floating', which atd cannot simulate; use revolute, continuous, prismatic"),
    (lambda t: t.format(kind="revolute").replace("arm.obj", "forearm.obj"),
     ":8: mesh 'package://meshes/forearm.obj' is not there (looked for"),
    (lambda t: t.format(kind="revolute").replace('lower="-1" upper="1"', 'lower="1" upper="-1"'),
     ":13: joint 'shoulder' has lower 1 >= upper -1; give its range with lower below upper"),
    (lambda t: t.format(kind="revolute").replace('effort="10" ', ""),
     ":13: <limit> has no 'effort'; add effort=\"...\""),
    (lambda t: t.format(kind="revolute").replace('<mass value="1.5"/>', '<mass value="heavy"/>'),
     ":6: value=\"heavy\" is not a number"),
    (lambda t: t.format(kind="revolute").replace("<box", "<capsule"),
     ":3: <capsule> is not a URDF geometry; use box, cylinder, sphere or mesh"),
    (lambda t: t.format(kind="revolute").replace("</robot>", "<robot>"),
     "not well-formed XML"),
    (lambda t: t.format(kind="revolute").replace("</visual>", '<material name="m"><color rgba="red"/></material></visual>'),
     ':8: rgba="red" is not four numbers in [0, 1]; write rgba="r g b a"'),
])
def test_what_cannot_be_imported_names_the_urdfs_file_and_line(tmp_path, edit, message):
    path = _write(tmp_path, edit(URDF))
    with pytest.raises(UrdfError) as info:
        read_urdf(path)
    assert str(info.value).startswith(str(path)) and message in str(info.value)


@pytest.mark.parametrize(("name", "text", "message"), [
    ("arm.dae", "<COLLADA/>", ".dae meshes are not supported; use an STL or OBJ file"),
    ("arm.stl", "not a mesh", "not an STL file"),
    ("arm.obj", ARM_MM, "the mesh's largest extent"),  # millimetres without scale="0.001 ..."
])
def test_a_collision_mesh_no_engine_could_take_is_named_at_its_line(tmp_path, name, text, message):
    path = _write(tmp_path, URDF.format(kind="revolute").replace(
        '<cylinder radius="0.03" length="0.2"/>', f'<mesh filename="meshes/{name}"/>'))
    (tmp_path / "meshes" / name).write_text(text)
    with pytest.raises(UrdfError) as info:
        read_urdf(path)
    assert str(info.value).startswith(f"{path}:7: mesh {tmp_path / 'meshes' / name} cannot be simulated: ")
    assert message in str(info.value)


def test_a_visual_mesh_is_read_in_its_materials_colour_apart_from_the_collision_shapes(tmp_path):
    urdf = URDF.format(kind="revolute").replace(
        "</geometry></visual>", '</geometry><material name="blue"><color rgba="0 0 1 1"/></material></visual>')
    arm = read_urdf(_write(tmp_path, urdf)).links[1]
    (drawn,) = arm.visuals
    assert drawn.kind == "mesh" and drawn.mesh == tmp_path / "meshes" / "arm.obj" and drawn.rgba == (0, 0, 1, 1)
    assert [shape.kind for shape in arm.shapes] == ["cylinder"]  # what collides is the <collision>


def test_a_visual_mesh_no_engine_loads_leaves_the_link_drawn_as_its_collision_shapes(tmp_path):
    path = _write(tmp_path, URDF.format(kind="revolute").replace("meshes/arm.obj", "meshes/arm.dae"))
    (tmp_path / "meshes" / "arm.dae").write_text("<COLLADA/>")
    arm = read_urdf(path).links[1]
    assert arm.visuals == () and arm.shapes[0].kind == "cylinder"


def test_what_a_bare_frame_draws_is_drawn_by_its_parent(tmp_path):
    flange = """<link name="flange"><visual><origin xyz="0 0 0.05"/><geometry><sphere radius="0.01"/></geometry>
      </visual></link>
      <joint name="weld" type="fixed"><parent link="arm"/><child link="flange"/><origin xyz="0 0 0.2"/></joint>
    </robot>"""
    model = read_urdf(_write(tmp_path, URDF.format(kind="revolute").replace("</robot>", flange)))
    assert [link.name for link in model.links] == ["base", "arm"]
    arm_mesh, sphere = model.links[1].visuals
    assert arm_mesh.kind == "mesh" and sphere.kind == "sphere" and sphere.origin.xyz == pytest.approx((0, 0, 0.25))


def test_a_broken_visual_mesh_is_named_at_its_line_as_a_collision_mesh_is(tmp_path):
    path = _write(tmp_path, URDF.format(kind="revolute"))
    (tmp_path / "meshes" / "arm.obj").write_text("v 0 0 0\nv 0.1 0.1 0.1\n")  # two points, no faces
    with pytest.raises(UrdfError) as info:
        read_urdf(path)
    assert str(info.value).startswith(f"{path}:8: mesh {tmp_path / 'meshes' / 'arm.obj'} cannot be simulated: ")
    assert "has no faces" in str(info.value)
