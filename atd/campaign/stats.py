"""Confidence in a success rate measured from a handful of trials.

The Wilson score interval stays inside [0, 1] and is honest at 0 or n successes out of n,
where the normal approximation claims certainty after ten trials.
"""

from __future__ import annotations

import math

#: The standard normal quantile for a two-sided 95% interval.
Z95 = 1.959963984540054


def wilson(successes: int, n: int, z: float = Z95) -> tuple[float, float]:
    """The 95% Wilson score interval (low, high) of `successes` out of `n`; (0, 1) when n is
    0, since no trial says nothing."""
    if not 0 <= successes <= n:
        raise ValueError(f"successes must be within 0..n, got {successes} of {n}")
    if n == 0:
        return 0.0, 1.0
    p = successes / n
    z2n = z * z / n
    centre = (p + z2n / 2) / (1 + z2n)
    half = z / (1 + z2n) * math.sqrt(p * (1 - p) / n + z2n / (4 * n))
    return max(0.0, centre - half), min(1.0, centre + half)
