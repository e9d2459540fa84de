"""The arm side of the naive baseline grasp of thesis 3.4.1; the robust grasp's is in
`primitives.arm.robust_approach`. Its phases are `NaivePhase`; it approaches as the robust
grasp does (`Approaching`) and raises `contact` when the hand may close."""

from __future__ import annotations

import numpy as np

from primitives.arm.approach_phases import SETTLE, Approaching, NaivePhase
from primitives.arm.motion import GAIN, clamp_norm, norm, orientation_twist, unit
from primitives.arm.move import arm_output
from primitives.base import Context, ControlData, Controller, Status
from primitives.filters import ContactWrench
from primitives.robot import Readings

BACK_OFF = 0.002  # m the naive approach settles short of its contact: fingers do not close pressing on it
PREGRASP_SPEED = 0.05  # m/s back to the pregrasp pose: a move in free air, away from the object
ARRIVED = 0.001  # m from the pregrasp pose: there


class NaiveGraspApproach(Controller):
    """The naive grasp's arm (thesis 3.4.1). The task's approach brought the hand to the
    grasp pose it planned; the thesis's naive grasp starts from the pregrasp pose, `distance`
    back from it along the grasp direction (PREGRASP). Still there, the hand preshaped, the
    wrist is read afresh (SETTLE); then forward until the wrist feels a contact or
    `distance` is covered, back at the grasp pose (APPROACH); then it stays BACK_OFF short
    of where it stopped, so that the fingers do not close pressing on what they hit, and
    lets the hand close (HOLD). No alignment, no riding the surface: the baseline the
    robust grasp is measured by."""

    def __init__(self, ctx: Context) -> None:
        super().__init__(ctx)
        p = self.params
        self.direction = unit(p["grasp_direction"])
        self.distance = float(p["distance"])
        self.threshold = float(p["force_threshold"])
        self.velocity = float(p["velocity"])
        self.contact = ContactWrench(float(p["filter_time"]))

    def start(self, readings: Readings) -> None:
        self.rotation = readings.tcp[:3, :3].copy()
        self.goal = readings.tcp[:3, 3] - self.distance * (self.rotation @ self.direction)  # the pregrasp pose
        self.phase = NaivePhase.PREGRASP
        self.still = 0.0  # s settled at the pregrasp pose
        self.ctx.blackboard.contact = False

    def update(self, readings: Readings, dt: float) -> ControlData:
        v = getattr(self, self.phase.value)(readings, dt)
        w, _ = orientation_twist(self.rotation, readings.tcp[:3, :3])
        return arm_output(np.concatenate([v, w]))

    # -- phases: one tick each, the world-frame velocity ----------------------------------
    def _pregrasp(self, readings: Readings, dt: float) -> np.ndarray:
        to_go = self.goal - readings.tcp[:3, 3]
        if norm(to_go) < ARRIVED:
            self.phase = NaivePhase.SETTLE
        return clamp_norm(GAIN * to_go, PREGRASP_SPEED)

    def _settle(self, readings: Readings, dt: float) -> np.ndarray:
        position = readings.tcp[:3, 3]
        ready = norm(self.goal - position) < ARRIVED and self.ctx.blackboard.preshaped
        self.still = self.still + dt if ready else 0.0
        if self.still >= SETTLE:
            self.contact.start(readings)  # the wrist's reading is the free hand's
            self.approaching = Approaching(position.copy())
            self.phase = NaivePhase.APPROACH
        return GAIN * (self.goal - position)

    def _approach(self, readings: Readings, dt: float) -> np.ndarray:
        self.contact.update(readings, dt)
        travelled = self.approaching.travelled(readings, self.direction)
        if self.contact.force >= self.threshold:
            self._stop(readings, f"contact after {travelled * 100:.1f} cm")
        elif travelled >= self.distance:
            self._stop(readings, f"moved {travelled * 100:.1f} cm without a contact")
        else:
            return readings.tcp[:3, :3] @ self.approaching.velocity(self.direction, self.velocity, dt)
        return np.zeros(3)

    def _hold(self, readings: Readings, dt: float) -> np.ndarray:
        return GAIN * (self.goal - readings.tcp[:3, 3])

    def _stop(self, readings: Readings, reason: str) -> None:
        self.goal = readings.tcp[:3, 3] - BACK_OFF * (readings.tcp[:3, :3] @ self.direction)
        self.phase = NaivePhase.HOLD
        self.ctx.blackboard.contact = True
        self.finish(Status.DONE, reason)
