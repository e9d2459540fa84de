"""The robust grasp on Tombatossals' three-finger hands: the Barrett (right arm) through the
seed tasks, the Schunk SDH2 (left arm) through a grasp-and-lift machine."""

from __future__ import annotations

import numpy as np
import pytest

from atd.model.vocabulary import EventType
from atd.sim.scene import box_scene
from tests.primitives.conftest import (
    EXAMPLES,
    Stage,
    both_done,
    events,
    execute,
    last_reasons,
    leaf,
    machine,
    run_example,
    simulated,
    tcp,
    use,
)


def test_barrett_picks_and_places_the_box() -> None:
    outcome, executor, robot = run_example(EXAMPLES / "pick_and_place.xml", robot="tombatossals", arm="right")
    assert outcome.succeeded, outcome.summary
    box = robot.object_pose()[:3, 3]
    assert np.linalg.norm(box - (0.10, 0.10, 0.025)) < 0.02, f"the box ended at {box}"
    grasped = [r for r in events(executor) if r["state"] == "grasp" and r["event"] == "success"][0]
    held = next(c["reason"] for c in grasped["conditions"] if c["kind"] == "hand_done")
    assert held.startswith("object held after 0 corrections, its weight ")  # weighed, and near the pinch line
    assert "tactile_f1 " in held and "tactile_f2 " in held and "tactile_f3" not in held  # a pinch: F1 against F2


def test_barrett_grasps_and_lifts_the_cylinder() -> None:
    outcome, _, robot = run_example(EXAMPLES / "grasp_and_lift.xml", robot="tombatossals", arm="right")
    assert outcome.succeeded, outcome.summary
    assert robot.object_pose()[2, 3] > 0.14


def _sdh2_grasp(scene) -> tuple:
    robot = simulated("tombatossals", "left", scene)
    grasp = dict(preshape="pinch_grasp_preshape", grasp_shape="pinch_grasp", pregrasp_size=0.64)
    estd = machine(
        Stage(use("cartesian_move", target=(0.125, 0.0, 0.03), straight_line=True),
              use("hand_shape", shape="pinch_grasp_preshape"), both_done()),
        Stage(use("robust_grasp_approach"), use("robust_grasp_hand", **grasp), both_done(), seconds=20.0),
        Stage(use("cartesian_move", target=(0.125, 0.0, 0.15), straight_line=True), use("hold_position"),
              both_done()),
        failures={"s1": (EventType.ERROR, leaf("hand_error"))},
    )
    return robot, *execute(estd, robot)


def test_sdh2_robust_grasp_holds_the_box_up() -> None:
    robot, outcome, executor = _sdh2_grasp(box_scene())
    assert outcome.succeeded, outcome.summary
    assert robot.object_pose()[2, 3] > 0.12
    pads = robot.read().pad_force
    assert pads[0] > 1.0 and pads[1] > 1.0  # the two pinching fingers still press
    grasp_events = [r for r in events(executor) if r["state"] == "s1"]
    reason = next(c["reason"] for c in grasp_events[0]["conditions"] if c["kind"] == "hand_done")
    assert reason.startswith("object held")


def test_robust_grasp_on_nothing_is_a_hand_error() -> None:
    robot, outcome, executor = _sdh2_grasp(box_scene(xy=(0.0, 0.25)))
    assert not outcome.succeeded
    reason = events(executor)[-1]["conditions"][0]["reason"]
    assert reason.startswith("nothing between the fingers after 5 corrections")
    assert tcp(robot)[2] < 0.03  # it looked across the pinch line, both ways twice, then further down, then gave up


@pytest.mark.parametrize("engine", ["mujoco", "pybullet"])
def test_barrett_finger_lost_correction_shifts_the_hand_onto_the_object(engine: str) -> None:
    """A heavy box 4 cm off the grasp centre along the pinch: F1 closes on it, F2 on
    nothing; the hand reopens and shifts towards F1 until both fingers hold it."""
    robot = simulated("tombatossals", "right", box_scene(xy=(0.165, 0.0), mass=5.0), engine)
    pinch = dict(preshape="pinch_grasp_preshape", grasp_shape="pinch_grasp")
    estd = machine(
        Stage(use("cartesian_move", target=(0.125, 0.0, 0.03), straight_line=True),
              use("hand_shape", shape="pinch_grasp_preshape"), both_done()),
        Stage(use("robust_grasp_approach"), use("robust_grasp_hand", **pinch), both_done(), seconds=40.0),
    )
    outcome, executor = execute(estd, robot)
    assert outcome.succeeded, outcome.summary
    held = next(c["reason"] for c in events(executor)[-1]["conditions"] if c["kind"] == "hand_done")
    assert held.startswith("object held after") and "after 0 corrections" not in held, held
    assert tcp(robot)[0] > 0.145  # the hand went to the box; the box did not come to the hand
    assert abs(robot.object_pose()[0, 3] - 0.165) < 0.006  # nudged while closing: 3.7 mm on main, 5.1 mm since holds must settle


def test_barrett_asked_more_than_its_fingers_press_holds_at_its_strongest_squeeze_and_says_so() -> None:
    """A grasp force beyond what the fingers can press: with every finger at its effort
    limit and the pads steady, the hold is all the hand has (docs/robust-grasp.md, evidence
    17): the grasp ends done, inside the 20 s the examples give it, saying the squeeze fell
    short of the force asked and what the pads feel."""
    robot = simulated("tombatossals", "right", box_scene())
    pinch = dict(preshape="pinch_grasp_preshape", grasp_shape="pinch_grasp", grasp_force=150.0)
    estd = machine(
        Stage(use("cartesian_move", target=(0.125, 0.0, 0.03), straight_line=True),
              use("hand_shape", shape="pinch_grasp_preshape"), both_done()),
        Stage(use("robust_grasp_approach"), use("robust_grasp_hand", **pinch), both_done(), seconds=20.0),
        failures={"s1": (EventType.ERROR, leaf("hand_error"))},
    )
    outcome, executor = execute(estd, robot)
    assert outcome.succeeded, outcome.summary
    held = next(r for r in last_reasons(executor) if r.startswith("object held"))
    assert held.endswith("(the hand's strongest squeeze, short of the 150.0 N asked)"), held
    assert "tactile_f1 " in held and "tactile_f2 " in held, held
