"""The naive baseline grasp of thesis 3.4.1 (from the pregrasp pose forward until contact,
close, squeeze a little) on a three-finger hand and on a gripper."""

from __future__ import annotations

from dataclasses import replace

import pytest

from atd.model import load_task
from atd.model.vocabulary import EventType
from atd.sim import load_description, make_robot
from atd.sim.scene import scene_from_task
from factories.registry import create
from tests.primitives.conftest import (
    EXAMPLES,
    Stage,
    both_done,
    events,
    execute,
    last_reasons,
    leaf,
    machine,
    melfa,
    use,
)
from translator import translate


def _naive_pick(robot, preshape: str, naive_hand) -> tuple:
    estd = machine(
        Stage(use("cartesian_move", target=(0.125, 0.0, 0.03), straight_line=True), use("hand_shape", shape=preshape),
              both_done()),
        Stage(use("naive_grasp_approach"), naive_hand, both_done()),
        Stage(use("cartesian_move", target=(0.125, 0.0, 0.15), straight_line=True), use("hold_position"),
              both_done()),
        failures={"s1": (EventType.ERROR, leaf("hand_error"))},
    )
    return execute(estd, robot)


def _naive_lift(robot: str, arm: str | None, moved: tuple[float, float] = (0.0, 0.0)) -> tuple:
    """grasp_and_lift.xml with the naive grasp, its cylinder moved by `moved` (m) from where
    the ATD believes it; the TCP's height through the grasp state, sampled every tick."""
    path = EXAMPLES / "grasp_and_lift.xml"
    task, _ = load_task(path)
    estd = translate(task, create(robot, arm, grasp="naive")).estd
    scene = scene_from_task(task, path)
    pose = scene.object.pose.copy()
    pose[:2, 3] += moved
    sim = make_robot(load_description(robot, arm), replace(scene, object=replace(scene.object, pose=pose)), "mujoco")
    heights: list[float] = []

    def hook(robot, where: str, time: float) -> None:
        if where == "grasp_object":
            heights.append(float(robot.read().tcp[2, 3]))

    outcome, executor = execute(estd, sim, hook, task=task)
    return outcome, executor, sim, heights


@pytest.mark.parametrize("arm", ["right", "left"])
def test_naive_grasp_comes_from_the_pregrasp_pose_and_lifts(arm: str) -> None:
    """Thesis 3.4.1: from the pregrasp pose, 10 cm back from the grasp pose the approach
    planned, forward until a contact or 10 cm, close, no corrections. Started at the grasp
    pose, its 10 cm ran the fingertips into the table and the SDH2 lifted nothing."""
    outcome, executor, sim, heights = _naive_lift("tombatossals", arm)
    assert outcome.succeeded, outcome.summary
    assert sim.object_pose()[2, 3] > 0.12
    assert max(heights) - heights[0] == pytest.approx(0.10, abs=0.003)  # back to the pregrasp pose first
    closed = [r for r in events(executor) if r["transition"].startswith("grasp_object->")][0]
    reasons = [c.get("reason") for c in closed["conditions"] if c.get("reason")]
    assert reasons[0] == "moved 10.0 cm without a contact" or reasons[0].startswith("contact after"), reasons
    assert reasons[1].startswith("closed on the object; touching:"), reasons


def test_naive_grasp_closing_on_nothing_is_an_error_not_a_lift() -> None:
    """Success is the pads' to say: with the cylinder 6 cm from where the ATD believes it,
    the fingers close on nothing and the grasp ends in an error saying so."""
    outcome, executor, sim, _ = _naive_lift("tombatossals", "left", moved=(0.0, 0.06))
    assert not outcome.succeeded
    assert last_reasons(executor) == ["nothing between the fingers"]
    assert sim.object_pose()[2, 3] < 0.05


def test_naive_grasp_lifts_the_box_with_the_melfa_gripper() -> None:
    robot = melfa()
    outcome, _ = _naive_pick(robot, "open", use("naive_grasp_hand"))
    assert outcome.succeeded, outcome.summary
    assert robot.object_pose()[2, 3] > 0.12


@pytest.mark.parametrize("engine", ["mujoco", "pybullet"])
def test_the_naive_baseline_on_a_gripper_grips_as_hard_as_the_robust_grasp(engine: str) -> None:
    """The baseline lacks the corrections, not the grip: with 10% of the Baxter's 20 N motor
    it pressed 2 N, never reached the 8 N its grasp_stable asks, and timed out on every
    object without error. It presses with the robust grasp's 20 N and lifts the cylinder."""
    path = EXAMPLES / "grasp_and_lift.xml"
    task, _ = load_task(path)
    estd = translate(task, create("baxter", grasp="naive")).estd
    (grasp,) = [s for s in estd.states if s.name == "grasp_object"]
    assert grasp.hand.name == "naive_grasp_hand" and grasp.hand.params["grasp_force"] == 20.0
    robot = make_robot(load_description("baxter"), scene_from_task(task, path), engine)
    outcome, _ = execute(estd, robot, task=task)
    assert outcome.succeeded, outcome.summary
    assert robot.object_pose()[2, 3] > 0.12
