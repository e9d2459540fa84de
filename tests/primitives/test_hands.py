"""The parallel-jaw gripper and the hand postures on the simulated Melfa (WRT-102)."""

from __future__ import annotations

import numpy as np

from atd.model.vocabulary import EventType
from atd.sim.scene import box_scene
from tests.primitives.conftest import Stage, both_done, execute, last_reasons, leaf, machine, melfa, tcp, use

STROKE = 0.034  # m per jaw, fully open
PADS = ("tactile_left", "tactile_right")


def _down_to(y: float) -> Stage:
    return Stage(use("cartesian_move", target=(0.125, y, 0.03), straight_line=True), use("hand_shape", shape="open"),
                 both_done())


def test_grasp_closes_to_the_grasp_force_and_lifts_the_box() -> None:
    robot = melfa()
    estd = machine(
        _down_to(0.0),
        Stage(use("hold"), use("close_until_force", grasp_force=15.0), both_done()),
        Stage(use("cartesian_move", target=(0.125, 0.0, 0.15), straight_line=True), use("squeeze", grasp_force=15.0),
              both_done()),
        Stage(use("hold"), use("squeeze", grasp_force=15.0), leaf("timeout", seconds=1.0)),
    )
    grasped: list = []

    def grip_offset(robot, state, time):
        if state == "s2" and not grasped:
            grasped.append(robot.object_pose()[:3, 3] - tcp(robot))

    outcome, executor = execute(estd, robot, grip_offset)
    assert outcome.succeeded, outcome.summary
    grasp_end = [r for r in executor.trace.records if r["type"] == "exit" and r["state"] == "s1"][0]
    assert grasp_end["duration"] < 1.5  # 34 mm at 20 mm/s, minus the box's 25 mm
    box = robot.object_pose()[:3, 3]
    assert box[2] > 0.13, f"the box is at z = {box[2]:.3f}, not lifted"
    slip = np.linalg.norm(box - tcp(robot) - grasped[0])
    assert slip < 0.001, f"the box slipped {slip * 1000:.1f} mm in the fingers"
    pads = robot.read().pad_force
    assert np.all(np.abs(pads - 15.0) < 1.5), f"pads feel {pads} N while squeezing with 15 N"


def test_grasp_recentres_on_an_off_centre_box() -> None:
    """A box 7 mm to the hand's left: one pad touches first; the arm follows that pad
    so the box is not shoved across the table."""
    robot = melfa(box_scene(xy=(0.125, 0.007)))
    estd = machine(_down_to(0.0), Stage(use("hold"), use("close_until_force", grasp_force=15.0), both_done()))
    before = robot.object_pose()[:3, 3]
    outcome, _ = execute(estd, robot)
    assert outcome.succeeded, outcome.summary
    moved = np.linalg.norm(robot.object_pose()[:2, 3] - before[:2])
    assert moved < 0.003, f"the box was pushed {moved * 1000:.1f} mm"
    assert abs(tcp(robot)[1] - 0.007) < 0.003  # the hand came to the box


def test_without_tactile_recentring_the_box_is_pushed() -> None:
    """The same grasp judged by the motor force alone cannot tell which jaw touches: the
    first jaw shoves the box 3.1 mm across the table (0.05 mm with the pads re-centring)."""
    robot = melfa(box_scene(xy=(0.125, 0.007)))
    estd = machine(_down_to(0.0), Stage(use("hold"), use("close_until_force", grasp_force=15.0, force_source="motor"),
                                        both_done()))
    before = robot.object_pose()[:3, 3]
    outcome, _ = execute(estd, robot)
    assert outcome.succeeded, outcome.summary
    assert np.linalg.norm(robot.object_pose()[:2, 3] - before[:2]) > 0.002


def test_closing_on_nothing_is_a_hand_error() -> None:
    robot = melfa(box_scene(xy=(0.0, 0.22)))
    estd = machine(Stage(use("hold"), use("close_until_force"), both_done()),
                   failures={"s0": (EventType.ERROR, leaf("hand_error"))})
    outcome, executor = execute(estd, robot)
    assert not outcome.succeeded
    assert last_reasons(executor) == ["the jaws closed on nothing"]


def test_release_opens_to_the_hand_position() -> None:
    robot = melfa(box_scene(xy=(0.0, 0.22)))
    estd = machine(Stage(use("hold"), use("hand_shape", shape="closed"), both_done()),
                   Stage(use("hold"), use("open_to", hand_position=0.5), both_done()))
    outcome, _ = execute(estd, robot)
    assert outcome.succeeded, outcome.summary
    assert abs(robot.read().hand_q[0] - 0.5 * STROKE) < 0.02 * STROKE


def test_a_shape_blocked_by_the_object_is_a_hand_error() -> None:
    robot = melfa()
    estd = machine(_down_to(0.0), Stage(use("hold"), use("hand_shape", shape="closed"), both_done()),
                   failures={"s1": (EventType.ERROR, leaf("hand_error"))})
    outcome, executor = execute(estd, robot)
    assert not outcome.succeeded
    assert "fingers blocked short of the posture" in last_reasons(executor)[0]
