"""A release whose fingers stop short of the opening lets go of what blocks them: the Baxter's
fingers, opened inside an espresso cup they had put down, stopped 3 mm short of open; the
release waited out its timeout and the cup hung on the rising hand for the rest of the run
(docs/empty-the-box.md, base seed 70919)."""

from __future__ import annotations

import numpy as np

from atd.model.estd import Controller
from atd.sim import load_description
from atd.sim.simrobot import robot_info
from primitives.base import Context, Status
from primitives.registry import build_controller
from primitives.robot import Readings

BAXTER = robot_info(load_description("baxter"))


def _fingers(q: float) -> Readings:
    """The Baxter's gripper at `q` (m), its pads feeling nothing (what blocks it is outside them)."""
    zeros = np.zeros(7)
    return Readings(time=0.0, arm_q=zeros, arm_dq=zeros, arm_effort=zeros, hand_q=np.array([q]),
                    hand_dq=np.zeros(1), hand_effort=np.zeros(1), tcp=np.eye(4), wrench=np.zeros(6), taxels={},
                    pad_force=np.zeros(2), range=None)


def test_fingers_blocked_opening_close_back_off_what_blocks_them_and_the_release_is_done() -> None:
    hand_info = BAXTER.hand
    assert hand_info.closing[0] < 0  # the gripper's q grows as it opens
    blocked_at = 0.85 * float(hand_info.upper[0])
    ctx = Context(info=BAXTER, params={}, environment=None)
    release = build_controller(Controller(name="open_to", params={"hand_position": 1.0}), "hand", ctx)
    release.start(_fingers(0.003))
    period = BAXTER.control_period
    commands = []
    for _ in range(round(5.0 / period)):  # the fingers open until something stops them, and stay there
        commands.append(float(release.update(_fingers(blocked_at), period).hand.values[0]))
        if release.status is not Status.RUNNING or max(commands) > blocked_at > commands[-1] + 0.0005:
            break
    assert release.status is Status.RUNNING, release.reason  # not an error, and not done: not yet free
    assert commands[-1] < blocked_at - 0.0005  # the fingers are told to close off what blocks them
    assert len(commands) * period < 2.5  # within the second that says they are blocked
    q = commands[-1]
    for _ in range(round(1.0 / period)):  # they follow
        q = float(release.update(_fingers(q), period).hand.values[0])
        if release.status is not Status.RUNNING:
            break
    assert release.status is Status.DONE
    assert "fingers blocked short of the opening 1" in release.reason and "backed off it" in release.reason
