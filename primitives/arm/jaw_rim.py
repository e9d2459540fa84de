"""Where along the jaws' width a closing finger pushed the object, read on the wrist.

A finger's bare rim beyond its pad can push an object lying along the jaws' width without
either pad feeling it: the jaws close on nothing and the pads say no side to look (the
Melfa's pads are 20 mm of its 30 mm fingers; docs/robust-grasp.md, "The rim, and a press
one pad does not feel"). The push is across the jaws (the hand's y), at a point x along
their width, so it turns the wrist about the approach axis by tau_z = x F_y; a vertical
press on the support adds nothing to tau_z. The lever x = tau_z / F_y (least squares over
the close) says where the object was met.
"""

from __future__ import annotations

import numpy as np

LEAST_PUSH = 0.1  # of the descent's contact threshold: a push across the jaws this strong is the object's, not noise


class RimLever:
    """The lever of the pushes across the jaws felt on the wrist during one close."""

    def __init__(self, threshold: float, band: float) -> None:
        self.least = LEAST_PUSH * threshold  # N across the jaws that count as a push
        # m: a lever nearer the hand's axis says no side: a bare fingertip below the pads, or noise
        self.band = band
        self.reset()

    def reset(self) -> None:
        """A new close begins: nothing pushed yet."""
        self.turn = 0.0  # sum of tau_z F_y over the pushes, N^2 m
        self.push = 0.0  # sum of F_y^2 over the pushes, N^2

    def add(self, wrench: np.ndarray) -> None:
        """One tick's contact wrench (force, torque) in the hand's axes."""
        across = float(wrench[1])
        if abs(across) >= self.least:
            self.turn += float(wrench[5]) * across
            self.push += across * across

    def lever(self) -> float | None:
        """m along the hand's x where the pushes were, `band` or more off it; None without one."""
        if self.push <= 0.0:
            return None
        lever = self.turn / self.push
        return lever if abs(lever) >= self.band else None
