"""The scene comes from the ATD: the object's class, size, pose, weight and friction, a mesh
next to the file, and the obstacles, in the same place on both engines."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from atd.model import Environment, ObjectClass, ObjectInfo, Obstacle, Pose, Task
from atd.model.task import ContainerInfo
from atd.sim.scene import SceneError, scene_from_task

CUBE_OBJ = """\
v -0.02 -0.02 -0.02
v 0.02 -0.02 -0.02
v 0.02 0.02 -0.02
v -0.02 0.02 -0.02
v -0.02 -0.02 0.02
v 0.02 -0.02 0.02
v 0.02 0.02 0.02
v -0.02 0.02 0.02
f 1 3 2
f 1 4 3
f 5 6 7
f 5 7 8
f 1 2 6
f 1 6 5
f 2 3 7
f 2 7 6
f 3 4 8
f 3 8 7
f 4 1 5
f 4 5 8
"""


def _task(**object_fields) -> Task:
    obstacles = (Obstacle(position=(0.2, -0.2, 0.05), size=(0.1, 0.1, 0.1)),)
    return Task(known_objects=(ObjectInfo(**object_fields),), environment=Environment(obstacles=obstacles))


def _at(x: float, y: float, z: float) -> Pose:
    return Pose.from_position((x, y, z))


def test_a_cylinder_from_the_atd_rests_where_the_atd_puts_it(melfa, robot_of, run, engine, tmp_path) -> None:
    task = _task(object_class=ObjectClass.CYLINDER, size=(0.03, 0.08), pose=_at(0.1, 0.1, 0.04), weight=0.3, friction=0.7)
    scene = scene_from_task(task, tmp_path / "task.xml")
    assert scene.object.mass == 0.3 and scene.object.friction == 0.7
    robot = robot_of(melfa, engine, scene)
    run(robot, 0.5)
    np.testing.assert_allclose(robot.object_pose()[:3, 3], (0.1, 0.1, 0.04), atol=1.5e-3)


def test_without_a_size_the_class_default_is_used(tmp_path) -> None:
    scene = scene_from_task(_task(object_class=ObjectClass.SPHERE), tmp_path / "task.xml")
    assert scene.object.kind == "sphere" and scene.object.size == (0.03,)
    assert scene.object.pose[2, 3] == pytest.approx(0.03)  # resting on the table when no pose is given


def test_an_obstacle_is_a_fixed_box_the_object_cannot_pass(melfa, robot_of, run, engine, tmp_path) -> None:
    # The object is dropped onto the obstacle: it must come to rest on top of it.
    task = _task(object_class=ObjectClass.BOX, size=(0.04, 0.04, 0.04), pose=_at(0.2, -0.2, 0.14))
    robot = robot_of(melfa, engine, scene_from_task(task, tmp_path / "task.xml"))
    run(robot, 0.5)
    np.testing.assert_allclose(robot.object_pose()[:3, 3], (0.2, -0.2, 0.12), atol=2e-3)


def test_a_mesh_next_to_the_atd_is_simulated(melfa, robot_of, run, engine, tmp_path) -> None:
    (tmp_path / "cube.obj").write_text(CUBE_OBJ)
    task = _task(shape="cube.obj", size=(0.04, 0.04, 0.04), pose=_at(0.05, 0.0, 0.03))
    scene = scene_from_task(task, tmp_path / "task.xml")
    assert scene.object.kind == "mesh"
    robot = robot_of(melfa, engine, scene)
    run(robot, 0.5)
    assert robot.object_pose()[2, 3] == pytest.approx(0.02, abs=2e-3)


def test_a_missing_mesh_names_the_file_and_the_fix(tmp_path: Path) -> None:
    with pytest.raises(SceneError) as err:
        scene_from_task(_task(shape="meshes/mug.stl"), tmp_path / "task.xml")
    message = str(err.value)
    assert "task.xml: <object> shape 'meshes/mug.stl'" in message
    assert str(tmp_path / "meshes" / "mug.stl") in message
    assert "put the mesh next to the ATD" in message


def test_an_unsupported_mesh_format_says_which_to_use(tmp_path: Path) -> None:
    (tmp_path / "mug.dae").write_text("<COLLADA/>")
    with pytest.raises(SceneError, match="use an STL or OBJ file"):
        scene_from_task(_task(shape="mug.dae"), tmp_path / "task.xml")


def test_a_world_mujoco_refuses_is_a_scene_error_not_its_traceback() -> None:
    """Nothing the validator accepts reaches here (sizes are 1 mm at least); built by hand, a
    body of almost no inertia is refused by MuJoCo's compiler in our words."""
    from atd.sim import make_robot
    from atd.sim.scene import SceneError, box_scene
    from factories.registry import create

    with pytest.raises(SceneError, match="MuJoCo cannot simulate this world: .*mjMINVAL"):
        make_robot(create("melfa").robot, box_scene(size=1e-9, mass=0.001), "mujoco")


def test_every_object_and_container_of_the_atd_is_in_the_scene_by_its_name(tmp_path) -> None:
    """Issue 31: a second named object is simulated, and the box the robot knows stands there."""
    mug, duck = ObjectInfo(name="mug", pose=_at(0.1, 0.1, 0.025)), ObjectInfo(name="duck", pose=_at(0.1, -0.1, 0.025))
    box = ContainerInfo(name="box", pose=_at(0.3, 0.0, 0.0), size=(0.3, 0.25, 0.1), wall=0.02)
    task = Task(known_objects=(mug, duck), environment=Environment(containers=(box,)))
    scene = scene_from_task(task, tmp_path / "task.xml")
    assert [b.name for b in scene.objects] == ["mug", "duck"]
    assert scene.objects[1].pose[1, 3] == pytest.approx(-0.1)
    assert scene.container("box").size == (0.3, 0.25, 0.1) and scene.container("box").wall == 0.02
