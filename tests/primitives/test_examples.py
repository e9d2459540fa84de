"""The seed tasks end to end: translated for the Melfa, run by the executor in MuJoCo."""

from __future__ import annotations

import numpy as np

from tests.primitives.conftest import EXAMPLES, run_example


def test_pick_and_place_puts_the_box_at_the_place_target() -> None:
    outcome, _, robot = run_example(EXAMPLES / "pick_and_place.xml")
    assert outcome.succeeded, outcome.summary
    assert [v.atd for v in outcome.visits] == ["approach", "descend", "grasp", "lift", "carry", "put_down", "let_go",
                                               "retreat", "done"]
    box = robot.object_pose()[:3, 3]
    assert np.linalg.norm(box - (0.10, 0.10, 0.025)) < 0.02, f"the box ended at {box}"
    assert abs(box[2] - 0.025) < 0.002  # on the table, not dropped on its side
    assert robot.read().hand_q[0] > 0.03  # released, hand open


def test_push_object_moves_the_box_along_y() -> None:
    outcome, _, robot = run_example(EXAMPLES / "push_object.xml")
    assert outcome.succeeded, outcome.summary
    box = robot.object_pose()[:3, 3]
    assert box[1] > 0.03, f"the box only reached y = {box[1]:.3f}"  # from -0.05: the pusher stops at y = 0.01
    assert abs(box[0] - 0.10) < 0.01 and abs(box[2] - 0.025) < 0.002  # straight, and still upright


def test_grasp_and_lift_holds_the_cylinder_up() -> None:
    outcome, _, robot = run_example(EXAMPLES / "grasp_and_lift.xml")
    assert outcome.succeeded, outcome.summary
    assert robot.object_pose()[2, 3] > 0.13  # lifted about 10 cm from 0.04
