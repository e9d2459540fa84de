"""A move that has arrived but still turns the hand is getting there, not stalled; one that
neither comes nearer nor turns is stalled after its patience (primitives/arm/motion.py)."""

from __future__ import annotations

import math

from primitives.arm.motion import STALL_TIME, Stall

TICK = 0.005  # s, the control period


def test_a_hand_that_has_arrived_but_still_turns_is_not_stalled_until_it_stops_turning() -> None:
    stall = Stall()
    stall.reset(0.0)
    angle = math.radians(20.0)
    t = 0.0
    while angle > math.radians(2.5):  # arrived at once; turning on at 3/s towards the goal, as a move does
        assert not stall.stalled(0.0, t, angle), f"stalled at {t:.2f} s with {math.degrees(angle):.1f} degrees to go"
        t += TICK
        angle -= 0.3 * angle * TICK  # slower than the move asks: a servo lagging its reference
    assert t > STALL_TIME  # it turned on for longer than a stall's patience
    stopped = t
    while not stall.stalled(0.0, t, angle):  # stuck 2.5 degrees short (a joint at its limit)
        t += TICK
    assert stopped + STALL_TIME - 0.5 < t < stopped + STALL_TIME + TICK


def test_a_motion_that_does_not_turn_is_stalled_by_distance_alone() -> None:
    stall = Stall()
    stall.reset(0.0, 0.05)
    assert not stall.stalled(0.0495, 1.0)  # half a millimetre nearer is no progress yet
    assert stall.stalled(0.0495, STALL_TIME + 0.01)
