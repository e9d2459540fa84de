"""The recent-rows window behind `fingers_still`: the rows of the last stretch of time, the
same whether kept in its buffer or rebuilt from every row seen, across its compactions and
growth, so a grip's spread reads as it did."""

from __future__ import annotations

import numpy as np

from primitives.filters import RecentRows


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
