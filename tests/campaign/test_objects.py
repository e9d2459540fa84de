"""The campaign's object library: ten and more everyday objects, believed as primitives,
simulated as real meshes from the installed pybullet_data where it has them."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pybullet_data
import pytest

from atd.campaign.objects import UnknownObject, get, library
from atd.campaign.trial import believed
from atd.model import Task, load_task
from atd.runtime.session import Run, belief_scene
from atd.sim import ENGINES, load_description, make_robot
from atd.model.meshcheck import mesh_points
from atd.sim.scene import Scene, bounding_box, scene_from_task
from factories.registry import create
from tests.conftest import EXAMPLES
from translator import translate

MESHED = [name for name, o in library().items() if o.mesh]
#: Where the objects rest alone: the unscrew task's place, clear of every hand at home (its TCP at
#: 0.125, 0, 0.15): at (0.1, 0) the Melfa's gripper base stood 18 mm inside a 205 mm bottle's cap,
#: at (0.12, 0.15) the open Barrett's fingers, 16 cm to either side, inside its cap and the
#: shampoo bottle's (the run's first move then met them).
CLEAR = tuple(load_task(EXAMPLES / "unscrew_by_touch.xml")[0].object.pose.position[:2])
#: The hand that reaches furthest from its TCP at home: the Barrett, its fingers open flat.
WIDEST = ("tombatossals", "right")


def _belief_body(name: str, x: float = 0.1, y: float = 0.0):
    return scene_from_task(Task(known_objects=(get(name).object_info(x, y),)), Path("campaign.xml")).object


def test_the_library_has_ten_everyday_objects_with_meshes_from_the_installed_pybullet_data() -> None:
    objects = library()
    assert len(objects) >= 10 and {"cylinder", "ball", "tape", "wood", "spray", "stapler", "weight"} <= set(objects)
    assert {"mug", "duck", "tape", "wood"} <= set(MESHED)
    data = Path(pybullet_data.getDataPath())
    for name in MESHED:
        truth = get(name).realize(_belief_body(name))
        assert truth.kind == "mesh" and data in truth.mesh.parents
    assert all(o.description and "\n" not in o.description for o in objects.values())


def test_an_unknown_object_is_refused_with_the_names_there_are() -> None:
    with pytest.raises(UnknownObject, match="no object 'mugg' in the library; choose one of: .*mug"):
        get("mugg")


def test_the_belief_rests_on_the_table_where_the_campaign_puts_it() -> None:
    info = get("spray").object_info(0.12, -0.05)
    assert info.pose.position == pytest.approx((0.12, -0.05, 0.0425))
    assert (info.object_class.value, info.size, info.weight, info.friction) == ("cylinder", (0.019, 0.085), 0.07, 0.5)


def test_a_campaign_object_stands_turned_as_the_task_turns_its_own() -> None:
    task_file = EXAMPLES / "campaigns" / "places" / "right_far.xml"  # at (0.20, -0.12), turned -60 degrees
    estd, _ = believed(str(task_file), "melfa", "main", "robust", "stapler")
    pose = estd.object.pose.as_array()
    assert pose[:3, 3] == pytest.approx((0.20, -0.12, 0.025))
    assert np.degrees(np.arctan2(pose[1, 0], pose[0, 0])) == pytest.approx(-60.0, abs=0.01)


@pytest.mark.parametrize("name", MESHED)
def test_the_truth_keeps_the_perturbed_pose_mass_and_friction_and_fills_the_believed_box(name: str) -> None:
    belief = _belief_body(name)
    pose = belief.pose.copy()
    pose[:3, 3] += (0.01, -0.02, 0.0)
    perturbed = dataclasses.replace(belief, pose=pose, mass=belief.mass * 1.3, friction=0.45)
    truth = get(name).realize(perturbed)
    assert np.array_equal(truth.pose, pose) and (truth.mass, truth.friction) == (perturbed.mass, 0.45)
    collided = np.vstack([mesh_points(f) for f in truth.collision_meshes])
    placed = collided * truth.mesh_scale @ truth.mesh_frame[:3, :3].T + truth.mesh_frame[:3, 3]
    np.testing.assert_allclose(placed.max(axis=0), -placed.min(axis=0), atol=1e-9)  # centred on the pose
    np.testing.assert_allclose(np.ptp(placed, axis=0), bounding_box(belief.kind, belief.size), rtol=1e-9)


@pytest.mark.parametrize("engine", ENGINES)
def test_every_object_rests_on_the_table_where_it_is_believed(engine: str) -> None:
    barrett = load_description(*WIDEST)
    for name in library():
        truth = get(name).realize(_belief_body(name, *CLEAR))
        robot = make_robot(barrett, Scene(truth), engine)
        try:
            for _ in range(round(0.5 / robot.info.control_period)):
                robot.step()
            pose = robot.object_pose()
        finally:
            robot.close()
        # PyBullet keeps a convex mesh about 1.5 mm off the table (its collision margin).
        assert np.linalg.norm(pose[:3, 3] - truth.pose[:3, 3]) < 3e-3, f"{name} on {engine} moved to {pose[:3, 3]}"
        assert pose[2, 2] > np.cos(np.radians(2)), f"{name} on {engine} tipped over"


@pytest.mark.parametrize("engine", ENGINES)
def test_the_melfa_lifts_the_espresso_cup(engine: str) -> None:
    cup = get("mug")
    task, _ = load_task(EXAMPLES / "grasp_and_lift.xml")
    factory = create("melfa", grasp="robust")
    estd = translate(task.model_copy(update={"object": cup.object_info(0.10, 0.0)}), factory).estd
    belief = belief_scene(estd)
    truth = Scene(cup.realize(belief.object), belief.obstacles, belief.table)
    run = Run(estd, factory, engine=engine, scene=truth)
    outcome = run.execute()
    assert outcome.succeeded
    assert run.object_position[2] - truth.object.pose[2, 3] > 0.05  # the ground truth: it rose 5 cm


def test_the_sdh2_lifts_the_bunny_it_cannot_squeeze_to_the_grasp_force() -> None:
    """The SDH2's links beside its pads carry part of the squeeze around the bunny's body:
    with both fingers at their effort limit the pads feel 2-3 N of the 5 N asked. The grasp
    holds there and the lift (the wrist feeling the weight) says whether it carries."""
    bunny = get("bunny")
    task, _ = load_task(EXAMPLES / "grasp_and_lift.xml")
    factory = create("tombatossals", "left", grasp="robust")
    estd = translate(task.model_copy(update={"object": bunny.object_info(0.10, 0.0)}), factory).estd
    belief = belief_scene(estd)
    truth = Scene(bunny.realize(belief.object), belief.obstacles, belief.table)
    run = Run(estd, factory, engine="mujoco", scene=truth)
    outcome = run.execute()
    assert outcome.succeeded, outcome.summary
    assert run.object_position[2] - truth.object.pose[2, 3] > 0.05  # the ground truth: it rose 5 cm
