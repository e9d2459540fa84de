"""Pushes must move the object: examples/push_object.xml on the hands that passed over the
box before, and a push that meets nothing, which must fail rather than report success."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from atd.model import load_task
from atd.model.vocabulary import EventType
from factories.registry import create
from tests.primitives.conftest import (EXAMPLES, Stage, both_done, events, execute, last_reasons, leaf, machine,
                                       melfa, run_example, tcp, use)
from translator import translate

PUSH = EXAMPLES / "push_object.xml"
BOX_START_Y = -0.05


@pytest.mark.parametrize("arm", ["right", "left"])
def test_tombatossals_pushes_the_box_at_least_5_cm_with_either_hand(arm: str) -> None:
    outcome, _, robot = run_example(PUSH, robot="tombatossals", arm=arm)
    assert outcome.succeeded, outcome.summary
    box = robot.object_pose()[:3, 3]
    assert box[1] - BOX_START_Y >= 0.05, f"the box only moved {100 * (box[1] - BOX_START_Y):.1f} cm"
    assert abs(box[2] - 0.025) < 0.002  # slid upright, not tipped over


def _box_out_of_the_way(tmp_path: Path) -> Path:
    """The push example with the box 12 cm further from the robot than the hand's path."""
    moved = PUSH.read_text().replace("1 0 0 0.10  0 1 0 -0.05", "1 0 0 0.22  0 1 0 -0.05")
    assert moved != PUSH.read_text()
    path = tmp_path / "push_nothing.xml"
    path.write_text(moved)
    return path


@pytest.mark.parametrize("robot, arm", [("melfa", None), ("tombatossals", "right")])
def test_a_push_that_touches_nothing_fails_on_error(tmp_path: Path, robot: str, arm: str | None) -> None:
    outcome, executor, _ = run_example(_box_out_of_the_way(tmp_path), robot=robot, arm=arm)
    assert not outcome.succeeded
    assert [v.atd for v in outcome.visits][-2:] == ["push", "failed"]
    fired = events(executor)[-1]
    assert fired["event"] == "error"
    assert "without pushing anything" in str(fired["conditions"])


@pytest.mark.parametrize("arm", ["right", "left"])
def test_a_closed_three_finger_hand_pushes_with_its_pointing_finger_at_the_path(arm: str) -> None:
    """The fist's sloping links wedged the box in PyBullet: the hand points one finger down
    instead, and its tip, not the TCP, follows the path."""
    task, _ = load_task(PUSH)
    factory = create("tombatossals", arm)
    estd = translate(task, factory).estd
    push = next(s for s in estd.states if s.atd == "push")
    hand = factory.robot.hand
    assert push.arm.name == "push"
    assert push.hand.params["shape"] == hand.push_posture == "push"
    tip = np.asarray(push.arm.params["target"]) + factory._hand_down @ np.array(hand.grasp_centres["push"][:2] + (0.0,))
    assert tip[:2] == pytest.approx((0.10, 0.01), abs=1e-6)
    assert tip[2] - factory.robot.hand_reach("push") == pytest.approx(0.035, abs=1e-6)  # the lowest point


def test_a_push_too_short_to_measure_its_free_motion_says_to_start_further_away() -> None:
    robot = melfa()
    start = tcp(robot)
    short = machine(Stage(use("push", target=tuple(start + (0.0, 0.01, 0.0))), use("hold_position"), both_done()),
                    failures={"s0": (EventType.ERROR, leaf("arm_error"))})
    outcome, executor = execute(short, robot)
    assert not outcome.succeeded
    assert any("start the push further from the object" in r for r in last_reasons(executor)), outcome.summary
