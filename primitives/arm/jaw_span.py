"""Where the object's top spans along the open jaws' width, seen by a range sensor looking
along the approach axis (Baxter's IR) while the hand moves along that width at grasp height.

A jaw grasp that finds the object across its jaws does not find it along them: the jaws
close wherever they straddle it, and a Baxter's paddles held a box 3.2-4.0 cm off their
middle, which its place, unable to weigh it, set down that far from the target
(docs/pick-and-place.md). The beam drops onto the top, or off it, by the object's height;
where it does, along the sweep, is an edge of the top, and the top's middle lies halfway
between its two edges.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


class BeamSpan:
    """The top's edges along one line, from successive (position along it, range) samples: a
    range that falls by more than `step` from one sample to the next is the beam coming onto
    the top, one that rises by more the beam leaving it; which edge that is follows from the
    way the beam moved."""

    def __init__(self, step: float) -> None:
        self.step = step  # m: half the object's believed height
        self.low: float | None = None  # m along the line: the top's edge on the line's negative side
        self.high: float | None = None  # the edge on its positive side
        self.last: tuple[float, float] | None = None

    def add(self, at: float, seen: float) -> None:
        """A sample: the beam at `at` (m along the line) read `seen` (m; inf for nothing)."""
        if self.last is not None and at != self.last[0]:
            was_at, was = self.last
            rising = at > was_at
            if seen < was - self.step:  # onto the top: the edge is behind the beam
                self.low, self.high = (at, self.high) if rising else (self.low, at)
            elif seen > was + self.step:  # off the top: the edge was where the beam last read it
                self.low, self.high = (self.low, was_at) if rising else (was_at, self.high)
        self.last = (at, seen)

    @property
    def middle(self) -> float | None:
        """m along the line of the top's middle, once both its edges are seen around it."""
        if self.low is None or self.high is None or self.low >= self.high:
            return None
        return (self.low + self.high) / 2.0


@dataclass
class Sweep:
    """One sweep of the open jaws along their width: the points still to go to (`route`), the
    line the beam is read along (from `origin`, along `axis`), where the jaws close once the
    top's middle is seen (`close`, moved along to it) and where they were to close (`fallback`)."""

    origin: np.ndarray  # (3,) world: where the sweep looks from, risen clear of the top if it must
    close: np.ndarray  # (3,) world: where the jaws close, before the move along to the middle
    fallback: np.ndarray  # (3,) world: where the jaws were to close, the object not located
    axis: np.ndarray  # (3,) world unit vector: the jaws' width, level
    route: list[np.ndarray]
    beam: BeamSpan
    risen: bool = False  # at the sweep's height: from here on a contact is something in the way
    met: bool = False  # the sweep met something: it looks no more

    @property
    def looking(self) -> bool:
        """The beam still looks for the top's edges: the sweep is under way, clear of anything."""
        return self.risen and not self.met and self.beam.middle is None

    @property
    def located(self) -> bool:
        """The beam saw the top's middle, and nothing pushed in the sweep's way."""
        return self.beam.middle is not None and not self.met

    def blocked(self) -> None:
        """The sweep met something, which it would push along: back where it began, and on to
        where the jaws were to close."""
        self.met = True
        self.route = [self.origin, self.fallback]

    def look(self, position: np.ndarray, seen: float) -> bool:
        """The beam's range `seen` (m) with the TCP at `position` (world); True once the top's
        middle is seen, the route then over it and down to where the jaws close."""
        self.beam.add(float((position - self.origin) @ self.axis), seen)
        if self.beam.middle is None:
            return False
        along = self.beam.middle * self.axis
        self.route = [self.origin + along, self.close + along]
        return True
