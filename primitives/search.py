"""Where a grasp looks for an object it closed on nothing: the same pattern for jaws and fingers."""

from __future__ import annotations


def search_offsets(step: float, points: int) -> list[float]:
    """Offsets from where the search began, alternating sides: +s, -s, +2s, -2s, ... (`points` of them)."""
    return [(1 if k % 2 == 0 else -1) * step * (k // 2 + 1) for k in range(points)]
