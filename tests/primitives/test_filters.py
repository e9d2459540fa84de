"""The recent-rows window behind `fingers_still`: the rows of the last stretch of time, the
same whether kept in its buffer or rebuilt from every row seen, across its compactions and
growth, so a grip's spread reads as it did. The contact wrench's tare: not on a ringing wrist."""

from __future__ import annotations

import numpy as np

from primitives.filters import ContactWrench, RecentRows
from primitives.robot import Readings


def test_the_window_holds_exactly_the_rows_of_the_last_stretch_of_time() -> None:
    rng = np.random.default_rng(7)
    for window in (0.0, 0.02, 0.3, 2.0):  # none, a few rows, past the first capacity, past its double
        recent, seen = RecentRows(3, capacity=8), []
        for tick in range(600):
            if tick == 250:  # a new state: the window starts over
                recent.clear()
                seen.clear()
            now, row = tick * 0.005, rng.standard_normal(3)
            seen.append((now, row))
            recent.add(now, row, now - window)
            expected = np.array([r for t, r in seen if t >= now - window])
            np.testing.assert_array_equal(recent.rows(), expected)


def test_a_kept_row_is_a_copy_not_the_callers_array() -> None:
    recent, row = RecentRows(2), np.array([1.0, 2.0])
    recent.add(0.0, row, -1.0)
    row[:] = 9.0
    np.testing.assert_array_equal(recent.rows(), [[1.0, 2.0]])


def _reading(time: float, force: tuple[float, float, float]) -> Readings:
    zeros = np.zeros(6)
    return Readings(time=time, arm_q=zeros, arm_dq=zeros, arm_effort=zeros, hand_q=zeros[:1], hand_dq=zeros[:1],
                    hand_effort=zeros[:1], tcp=np.eye(4), wrench=np.concatenate((force, zeros[:3])), taxels={},
                    pad_force=zeros[:0], range=None)


# The Melfa's wrist force, 5 ms apart, as the move after the unscrew's put-down began (MuJoCo, the
# jam jar, main at 4c78863): the cap's knock on the table still rang; 13.8 N up is hand and cap hanging.
RING = ((-2.07, -0.58, -1.25), (2.92, 4.96, 4.10), (0.28, 0.33, 12.46), (-0.25, -0.14, 13.16),
        (-0.40, -0.15, 13.40), (-0.19, -0.06, 13.61), (-0.17, -0.12, 13.76), (-0.02, -0.06, 13.81),
        (0.04, -0.01, 13.76), (-0.00, -0.02, 13.80), (-0.03, 0.00, 13.85)) + ((0.0, 0.0, 13.8),) * 20
HANGING = (0.0, 0.0, 13.8)


def test_a_tare_taken_as_the_wrist_still_rings_follows_it_until_it_is_still() -> None:
    wrench = ContactWrench()
    wrench.start(_reading(0.0, RING[0]))
    felt = []
    for i, force in enumerate(RING[1:], 1):
        wrench.update(_reading(0.005 * i, force), 0.005)
        felt.append(wrench.force)
    assert max(felt) < 0.5, max(felt)  # held on its first reading, it read 15 N: an unexpected contact
    wrench.update(_reading(0.2, (0.0, 0.0, 8.8)), 0.005)
    assert abs(wrench.force - 5.0) < 0.1  # a later contact reads in full


def test_a_start_that_does_not_ring_keeps_its_reading_and_a_tare_that_must_not_wait_sees_a_knock_at_once() -> None:
    still, at_once = ContactWrench(), ContactWrench()
    still.start(_reading(0.0, HANGING))
    at_once.start(_reading(0.0, HANGING), settle=False)
    for i in range(1, 41):  # still for 0.1 s, then a load rising 0.5 N a tick
        still.update(_reading(0.005 * i, (0.0, 0.0, 13.8 - 0.5 * max(0, i - 20))), 0.005)
    assert abs(still.force - 10.0) < 1e-9  # against the start's reading
    at_once.update(_reading(0.005, (0.0, 0.0, 3.8)), 0.005)
    assert abs(at_once.force - 10.0) < 1e-9
