"""A URDF becomes description links; what cannot be imported is named at its file:line."""

from __future__ import annotations

import textwrap
from pathlib import Path

import numpy as np
import pybullet_data
import pytest

from factories.urdf import UrdfError, read_urdf

PANDA = Path(pybullet_data.getDataPath()) / "franka_panda" / "panda.urdf"


def test_the_pandas_urdf_gives_its_tree_limits_masses_and_meshes_as_boxes():
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
    (box,) = hand.shapes  # the collision mesh's bounding box: the hand is about 20 cm across its fingers' travel
    assert box.kind == "box" and 2 * max(box.size) == pytest.approx(0.204, abs=0.002)
    # the right finger's mesh is turned half round about z: its box lies on the other side
    assert model.link("panda_rightfinger").shapes[0].origin.xyz[1] == pytest.approx(
        -model.link("panda_leftfinger").shapes[0].origin.xyz[1])


URDF = """\
<robot name="two">
  <link name="base">
    <collision><geometry><box size="0.2 0.2 0.1"/></geometry></collision>
  </link>
  <link name="arm">
    <inertial><origin xyz="0 0 0.1"/><mass value="1.5"/><inertia ixx="0.01" iyy="0.02" izz="0.03"/></inertial>
    <collision><origin xyz="0 0 0.1"/><geometry><cylinder radius="0.03" length="0.2"/></geometry></collision>
    <visual><geometry><mesh filename="package://meshes/arm.obj"/></geometry></visual>
  </link>
  <joint name="shoulder" type="{kind}">
    <parent link="base"/><child link="arm"/>
    <origin xyz="0 0 0.1" rpy="0 0 1.5708"/><axis xyz="0 0 2"/>
    <limit effort="10" velocity="1" lower="-1" upper="1"/><dynamics damping="0.5" friction="0.1"/>
  </joint>
</robot>
"""


def _write(tmp_path: Path, text: str, mesh: bool = True) -> Path:
    if mesh:
        (tmp_path / "meshes").mkdir(exist_ok=True)
        (tmp_path / "meshes" / "arm.obj").write_text("v 0 0 0\nv 0.1 0.2 0.3\n")
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
])
def test_what_cannot_be_imported_names_the_urdfs_file_and_line(tmp_path, edit, message):
    path = _write(tmp_path, edit(URDF))
    with pytest.raises(UrdfError) as info:
        read_urdf(path)
    assert str(info.value).startswith(str(path)) and message in str(info.value)
