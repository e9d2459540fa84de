"""The arm side of the naive baseline grasp of thesis 3.4.1; the robust grasp's is in
`primitives.arm.robust_approach`. It raises `contact` when the hand may close."""

from __future__ import annotations

import numpy as np

from primitives.arm.motion import GAIN, orientation_twist, unit
from primitives.arm.move import arm_output
from primitives.base import Context, ControlData, Controller, Status
from primitives.filters import ContactWrench
from primitives.robot import Readings

BACK_OFF = 0.002  # m the naive approach settles short of its contact: fingers do not close pressing on it


class NaiveGraspApproach(Controller):
    """The naive grasp's arm (thesis 3.4.1): forward along the grasp direction until the
    wrist feels a contact or `distance` is covered, then stay (BACK_OFF short of where it
    stopped, so the fingers do not close while pressing on what they hit) and let the
    hand close. No alignment, no riding the surface: the baseline the robust grasp is
    measured by."""

    def __init__(self, ctx: Context) -> None:
        super().__init__(ctx)
        p = self.params
        self.direction = unit(p["grasp_direction"])
        self.distance = float(p["distance"])
        self.threshold = float(p["force_threshold"])
        self.velocity = float(p["velocity"])
        self.contact = ContactWrench(float(p["filter_time"]))

    def start(self, readings: Readings) -> None:
        self.contact.start(readings)
        self.origin = readings.tcp[:3, 3].copy()
        self.rotation = readings.tcp[:3, :3].copy()
        self.ctx.blackboard.contact = False

    def update(self, readings: Readings, dt: float) -> ControlData:
        self.contact.update(readings, dt)
        rotation, position = readings.tcp[:3, :3], readings.tcp[:3, 3]
        if self.status is Status.RUNNING:
            travelled = float((position - self.origin) @ (rotation @ self.direction))
            if self.contact.force >= self.threshold:
                self._stop(position, rotation, f"contact after {travelled * 100:.1f} cm")
            elif travelled >= self.distance:
                self._stop(position, rotation, f"moved {travelled * 100:.1f} cm without a contact")
        v = GAIN * (self.goal - position) if self.status is Status.DONE else rotation @ (self.velocity * self.direction)
        w, _ = orientation_twist(self.rotation, rotation)
        return arm_output(np.concatenate([v, w]))

    def _stop(self, position: np.ndarray, rotation: np.ndarray, reason: str) -> None:
        self.goal = position - BACK_OFF * (rotation @ self.direction)
        self.ctx.blackboard.contact = True
        self.finish(Status.DONE, reason)
