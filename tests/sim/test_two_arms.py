"""Two arms of one robot in one world, in each engine: each behind its own robot interface,
the added one parked where its description says, and one step of the first moving both as
commanded."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from atd.sim import ENGINES, load_description, make_arms
from atd.sim.scene import SceneError
from atd.sim.two_arms import parked


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.parametrize("robot", ["baxter", "tombatossals"])
def test_both_arms_live_in_one_world_and_move_with_one_step(robot: str, engine: str) -> None:
    right, left = load_description(robot, "right"), load_description(robot, "left")
    first, second = make_arms((right, left), engine=engine)
    try:
        np.testing.assert_allclose(first.true_tcp()[:3, 3], right.tcp_pose(np.array(right.home))[:3, 3], atol=2e-3)
        assert second.true_tcp()[1, 3] > 0.29  # the left hand parked on its own side
        assert second.info.hand.dofs == tuple(d.name for d in left.hand.dofs)  # its own hand (SDH2 on Tombatossals)
        before = second.read().arm_q.copy(), first.read().arm_q.copy()
        speed = np.zeros(len(left.arm_joints))
        speed[0] = 0.2
        second.command_arm_velocity(speed)
        for _ in range(100):  # 0.5 s; the first arm is told nothing and holds
            first.step()
        moved, held = second.read().arm_q - before[0], first.read().arm_q - before[1]
        assert 0.05 < moved[0] < 0.1 and np.abs(moved[1:]).max() < 0.01
        assert np.abs(held).max() < 0.005
        assert second.read().time == first.read().time == pytest.approx(0.5)
    finally:
        first.close()


def test_an_added_arm_waits_where_its_description_parks_it() -> None:
    left = load_description("tombatossals", "left")
    elsewhere = parked(dataclasses.replace(left, park=(0.10, 0.25, 0.20)))
    tcp = elsewhere.tcp_pose(np.array(elsewhere.home))
    np.testing.assert_allclose(tcp[:3, 3], (0.10, 0.25, 0.20), atol=2e-3)
    assert tcp[2, 2] < -0.999  # the hand still points down
    with pytest.raises(SceneError, match="says nowhere for it to wait"):
        parked(dataclasses.replace(left, park=None))
