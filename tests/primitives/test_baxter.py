"""The shared arm controllers and the parallel-jaw grasp on Baxter: a noisy virtual wrist
wrench (filtered, higher thresholds) and a gripper that senses by its motor, not pads."""

from __future__ import annotations

import numpy as np

from atd.model.estd import ConditionGroup
from atd.sim.scene import box_scene
from tests.primitives.conftest import EXAMPLES, Stage, both_done, execute, leaf, machine, run_example, simulated, use

NOISY = {"filter_time": 0.05}  # Baxter's config filters its virtual wrench


def test_baxter_pushes_the_box() -> None:
    outcome, _, robot = run_example(EXAMPLES / "push_object.xml", robot="baxter")
    assert outcome.succeeded, outcome.summary
    assert robot.object_pose()[1, 3] > 0.03


def test_baxter_grasp_and_lift_holds_the_cylinder_up() -> None:
    """The IR beam sees the held cylinder, so the grasp becomes stable and the lift follows."""
    outcome, _, robot = run_example(EXAMPLES / "grasp_and_lift.xml", robot="baxter")
    assert outcome.succeeded, outcome.summary
    assert robot.object_pose()[2, 3] >= 0.04 + 0.08, "the cylinder was not lifted 8 cm"


def test_baxter_pick_and_place_puts_the_box_at_the_place_target() -> None:
    outcome, _, robot = run_example(EXAMPLES / "pick_and_place.xml", robot="baxter")
    assert outcome.succeeded, outcome.summary
    box = robot.object_pose()[:3, 3]
    assert np.linalg.norm(box - (0.10, 0.10, 0.025)) < 0.02, f"the box ended at {box}"


def test_baxter_grasps_by_motor_force_places_and_releases() -> None:
    robot = simulated("baxter", scene=box_scene())
    squeeze = use("squeeze", grasp_force=20.0, force_source="motor")
    gripped = ConditionGroup(op="all", children=(
        both_done(), leaf("gripper_force_above", "gripper", force_threshold=8.0, for_time=0.1),
        leaf("gripper_opening_above", "gripper", width=0.004, for_time=0.1)))
    target = (0.125, 0.1, 0.025)
    estd = machine(
        Stage(use("cartesian_move", target=(0.125, 0.0, 0.03), straight_line=True, force_threshold=30.0, **NOISY),
              use("hand_shape", shape="open"), both_done()),
        Stage(use("hold"), use("close_until_force", grasp_force=20.0, force_source="motor"), gripped),
        Stage(use("cartesian_move", target=(0.125, 0.1, 0.08), force_threshold=30.0, **NOISY), squeeze, both_done()),
        Stage(use("place", target=target, force_threshold=10.0, **NOISY), squeeze, both_done()),
        Stage(use("release_retreat", force_threshold=10.0, **NOISY), use("open_to"), both_done()),
    )
    outcome, _ = execute(estd, robot)
    assert outcome.succeeded, outcome.summary
    box = robot.object_pose()[:3, 3]
    assert np.linalg.norm(box - target) < 0.005, f"the box ended at {box}"
