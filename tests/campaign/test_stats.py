"""The 95% Wilson score interval against published values."""

from __future__ import annotations

import pytest

from atd.campaign.stats import wilson


@pytest.mark.parametrize(("successes", "n", "low", "high"), [
    (59, 100, 0.4920, 0.6813),  # thesis Table 3.3, robust + error
    (0, 10, 0.0, 0.2775),  # no success is not a rate of exactly 0
    (10, 10, 0.7225, 1.0),  # ten out of ten is not certainty
])
def test_wilson_interval_matches_known_values(successes: int, n: int, low: float, high: float) -> None:
    got = wilson(successes, n)
    assert got == pytest.approx((low, high), abs=1e-4)


def test_no_trials_say_nothing_and_impossible_counts_are_refused() -> None:
    assert wilson(0, 0) == (0.0, 1.0)
    with pytest.raises(ValueError, match="within 0..n"):
        wilson(11, 10)
