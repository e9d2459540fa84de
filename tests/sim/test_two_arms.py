"""Two arms of one robot in one MuJoCo world: each behind its own robot interface, the added
one parked beside the work area, and one step of the first moving both as commanded."""

from __future__ import annotations

import numpy as np
import pytest

from atd.sim import load_description, make_arms


@pytest.mark.parametrize("robot", ["baxter", "tombatossals"])
def test_both_arms_live_in_one_world_and_move_with_one_step(robot: str) -> None:
    right, left = load_description(robot, "right"), load_description(robot, "left")
    first, second = make_arms((right, left))
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
