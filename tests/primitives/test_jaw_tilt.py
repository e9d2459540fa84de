"""A jaw grasp keeps the tilt the approach left (turning it upright drove the Melfa's wrist onto
its limit), and a tilted hand's fingertip corner hangs lower than its middle: the descent closes
with every corner clear of the table, not only the middle (generalisation.toml: tilted 16
degrees, the Melfa's finger struck the table and the jolt was read as the object)."""

from __future__ import annotations

import numpy as np
import pytest

from atd.model.estd import Controller
from atd.sim import load_description
from factories.base import SWEEPING_TIP
from primitives.base import Context
from primitives.registry import build_controller
from tests.primitives.melfa_jaws import DOWN, MELFA, still

HAND = load_description("melfa")
REACH = HAND.hand_reach("open")
EXTENT = HAND.hand_extent("open", SWEEPING_TIP)


def _lowest_corner_at_close(tilt: float) -> float:
    """The jaw grasp's descent in free air, the hand rolled `tilt` degrees about the world's x:
    the height of the open fingertips' lowest corner when the jaws are told to close."""
    c, s = np.cos(np.radians(tilt)), np.sin(np.radians(tilt))
    rotation = np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]]) @ DOWN
    ctx = Context(info=MELFA, params={}, environment=None)
    arm = build_controller(Controller(name="jaw_grasp_correction", params={"fingertip_reach": REACH}), "arm", ctx)
    period, position = MELFA.control_period, np.array([0.4, 0.0, 0.10])

    def at() -> object:
        readings = still(tuple(position))
        readings.tcp[:3, :3] = rotation
        return readings

    arm.start(at())
    for _ in range(3000):
        if ctx.blackboard.contact:
            break
        position += arm.update(at(), period).arm.twist[:3] * period
    assert ctx.blackboard.contact
    corners = [rotation @ np.array([x * EXTENT[0], y * EXTENT[1], REACH]) for x in (-1, 1) for y in (-1, 1)]
    return float(position[2] + min(corner[2] for corner in corners))


@pytest.mark.parametrize("tilt", (0.0, 16.0))
def test_a_tilted_jaw_grasp_closes_with_its_lowest_fingertip_clear_of_the_table(tilt: float) -> None:
    assert _lowest_corner_at_close(tilt) >= 0.004
