"""Where a pinch looks for an object it closed on nothing: across the line its two fingers
close along, about where the hand first closed (docs/robust-grasp.md, "The search")."""

from __future__ import annotations

import numpy as np

from primitives.search import search_offsets

SEARCH_POINTS = 4  # points searched across the pinch line: two steps each side cover the seeds' 5 cm error
NUDGE = 1.5  # of a pad's half width: a step across the line clears the bare finger face a jam stood on


class PinchSearch:
    """The search across the pinch line of one grasp: the one place that keeps track of
    where across it the hand closes (`across`, m from where it first closed)."""

    def __init__(self, normal: np.ndarray | None, step: float, lost_step: float, pad_width: float) -> None:
        self.normal = normal  # unit vector across the pinch line (hand x, y); None: no pinch
        self.step = step  # m between search points
        self.lost_step = lost_step  # m along the approach: D5's step for hands that do not pinch
        self.pad_width = pad_width  # m: the widest grasping pad's half width across its finger
        self.plan = search_offsets(step, SEARCH_POINTS)  # search points not yet visited
        self.across = 0.0
        self.heading = 0.0  # the side (+1, -1) of a search step whose close is being judged, else 0
        self.weighed = False  # that step went to where the object was just weighed: it stood there
        self.nudged = 0  # nudges made after a jam: 0, then 1 (one side), -1 (both)

    def next(self, beyond: float = 0.0, side: float = 0.0) -> np.ndarray:
        """The shift (hand frame) to the next place to look: `step` to one side of where
        the hand first closed, then as far to the other, then twice as far each way, then
        D5's step along the approach. `beyond` (+1 or -1): the last step's close touched
        the object's edge on that side, so one step further that way instead. `side` (+1
        or -1): a pad felt the object that way of the hand on the close, so the nearest
        point not yet visited on that side comes first."""
        if self.normal is None or not (self.plan or beyond):
            return np.array([0.0, 0.0, self.lost_step])
        toward = [p for p in self.plan if (p - self.across) * side > 0.0]
        point = self.across + beyond * self.step if beyond else min(toward or self.plan[:1],
                                                                    key=lambda p: abs(p - self.across))
        self.plan = [p for p in self.plan if not np.isclose(p, point)]
        return self.look(point)

    def onward(self, heading: float) -> np.ndarray:
        """The close after a regrasp across to the object's weighed weight met nothing: the
        bare fingertips pushed it on, the way the regrasp went (docs/robust-grasp.md, "The
        regrasp that pushed the mug away"): one step further that way, once."""
        return self.next(beyond=heading)

    def look(self, point: float, weighed: bool = False) -> np.ndarray:
        """The shift to a new place to look, `point` across the pinch line: its close is
        judged heading the way the step went (`weighed`: to where the object was just weighed),
        and no nudge has been made there yet."""
        self.nudged = 0
        self.heading = float(np.sign(point - self.across))
        self.weighed = weighed
        return self._move(point)

    def nudge_pending(self, jammed: bool) -> bool:
        """The close jammed with neither side of it looked at yet, or the first nudge found nothing."""
        return (jammed and self.nudged == 0) or self.nudged == 1

    def nudge(self) -> np.ndarray:
        """The shift after fingers jammed on the object beside their pads: NUDGE pad half
        widths across the line, then as far the other side of where they jammed."""
        step = NUDGE * self.pad_width * (1.0 if self.nudged == 0 else -2.0)
        self.nudged = 1 if self.nudged == 0 else -1
        self.heading, self.weighed = 0.0, False
        return self._move(self.across + step)

    def _move(self, point: float) -> np.ndarray:
        step, self.across = point - self.across, point
        return step * np.array([*self.normal, 0.0])
