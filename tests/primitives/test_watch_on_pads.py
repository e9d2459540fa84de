"""A watched pinch ends on its pads, not on time alone: at generalisation seed 32856 the
Barrett held a duck 2.2 cm off its pinch line, the lift's 6 s watch passed with the pads
easing 0.15 N/s at the held effort, the lift said success and the duck slid out in the
judge's hold; watched lifts whose pads eased as fast dropped 3.5-4.5 s after their 6 s
(docs/robust-grasp.md, "A watched pinch ends on its pads"). Steady is read on the slope of the
whole last second, and a grip still easing holds at the bound ("A watched pinch says it holds on
a steady slope")."""

from __future__ import annotations

from pathlib import Path
from typing import Callable

import numpy as np

from atd.sim import load_description
from factories.robot_info import robot_info
from primitives.base import Context, Status
from primitives.blackboard import STEEP_PINCH
from primitives.hands.posture import STEEP_WATCH, HoldPosition
from primitives.robot import Readings, RobotInfo
from tests.primitives.conftest import campaign_trial, generalisation_at

DT = 0.005
BOUND = 2 * STEEP_WATCH  # s an easing pinch is watched before it counts as held
BARRETT = robot_info(load_description("tombatossals", "right"))


def _readings(info: RobotInfo, time: float, force: float, column: int) -> Readings:
    """Pads f1 and f2 each pressing `force` on one taxel of the last row, at `column`."""
    hand = info.hand
    images = {pad.name: None if pad.taxels is None else np.zeros(pad.taxels) for pad in hand.pads}
    forces = np.zeros(len(hand.pads))
    for i, pad in enumerate(hand.pads[:2]):
        images[pad.name][-1, column] = forces[i] = force
    zero = np.zeros(len(info.arm_joints))
    effort = np.where(hand.closing > 0, 0.2 * hand.effort_limit, 0.0)
    return Readings(time=time, arm_q=zero, arm_dq=zero, arm_effort=zero, hand_q=hand.lower.copy(),
                    hand_dq=np.zeros(len(hand.dofs)), hand_effort=effort, tcp=np.eye(4), wrench=np.zeros(6),
                    taxels=images, pad_force=forces, range=None)


def _ends(force: Callable[[float], float], column: Callable[[float], int] = lambda t: 0) -> tuple[Status, float, str]:
    """How a watched hold of the Barrett's pinch ends, and when, under pads reading `force(t)` at `column(t)`."""
    ctx = Context(info=BARRETT, params={"speed": 1.0}, memory={STEEP_PINCH: True})
    hold = HoldPosition(ctx)
    hold.start(_readings(BARRETT, 0.0, force(0.0), column(0.0)))
    time = 0.0
    while hold.status is Status.RUNNING and time < 2 * BOUND:
        time += DT
        hold.update(_readings(BARRETT, time, force(time), column(time)), DT)
    return hold.status, time, hold.reason


def test_a_steady_watched_pinch_holds_after_the_watch() -> None:
    noise = np.random.default_rng(0)  # the pads' scatter about their line in the traced holds: 0.003-0.006 N
    status, time, _ = _ends(lambda t: 5.0 - 0.002 * t + 0.005 * noise.standard_normal())
    assert status is Status.DONE and abs(time - STEEP_WATCH) < 2 * DT


def test_a_watched_pinch_whose_pads_ease_holds_only_at_the_bound() -> None:
    status, time, reason = _ends(lambda t: 5.4 - 0.15 * t)  # the duck that slid out after the 6 s watch
    assert status is Status.DONE and abs(time - BOUND) < 2 * DT, (status, time, reason)
    assert "easing" in reason


def test_one_noisy_reading_does_not_make_an_easing_pinch_steady() -> None:
    """The 50255 bunny's pads eased 1.6 %/s at 17 N; one reading 0.25 N low a second before
    makes the fall between two readings 1 s apart look steady (watch23's rule: held at 9 s here,
    at the bunny 11.4 s, 0.03 s before it let go)."""
    status, time, reason = _ends(lambda t: 17.5 - 0.28 * t - (0.25 if abs(t - 8.0) < DT / 2 else 0.0))
    assert status is Status.DONE and abs(time - BOUND) < 2 * DT, (status, time, reason)


def test_a_watched_pinch_that_settles_holds_once_steady() -> None:
    status, time, _ = _ends(lambda t: 5.0 - 0.15 * min(t, 8.0))
    assert status is Status.DONE and 8.5 < time < 9.5


def test_a_watched_pinch_whose_contacts_move_is_not_said_to_hold() -> None:
    # A contact creeping a taxel column (4.75 mm) every 0.5 s from 5 s to 7.5 s, the force steady.
    status, time, _ = _ends(lambda t: 5.0, lambda t: 0 if t < 5.0 else min(6, 1 + int((t - 5.0) / 0.5)))
    assert status is Status.DONE and 8.4 < time < 8.6


def test_a_watched_pinch_whose_pads_let_go_does_not_hold() -> None:
    status, time, reason = _ends(lambda t: max(0.0, 5.0 - 0.5 * t))  # nothing between the pads from 10 s
    assert status is Status.RUNNING, (status, time, reason)  # the lift's grasp_lost ends it


def test_a_lift_whose_duck_would_creep_out_after_the_watch_does_not_say_success(tmp_path: Path) -> None:
    """Seed 32856, right_far, the duck's trial 1: main said success at 6 s with the pads
    easing 0.1 N/s (3.8 %/s); the judge's 2 s hold passed, the duck slid out 3.5 s later."""
    record = campaign_trial(generalisation_at(32856, tmp_path), 1, "robot=tombatossals", "arm=right",
                            "engine=mujoco", "perturbation=approach", "task=right_far", "object=duck")
    assert not record.task_succeeded, (record.judge_reason, record.summary)
    assert "grasp_lost" in record.summary, record.summary
