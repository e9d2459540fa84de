"""Arm controllers that work against a supporting surface: place (Eq. 3.4) and release
retreat (Eq. 3.5) of thesis 3.3.3 - 3.3.4 (the slide, Eq. 3.6, is `primitives.arm.slide`).

Both read the contact wrench (tared at the state's start, see `ContactWrench`) and
the SURFACE_NORMAL n, a world vector pointing out of the surface: pressing on the
surface makes the contact force point along +n.
"""

from __future__ import annotations

import numpy as np

from primitives.arm.motion import (
    GAIN,
    ORIENTATION_TOLERANCE,
    TwistShaper,
    clamp_norm,
    orientation_twist,
    top_down,
    unit,
)
from primitives.arm.move import arm_output
from primitives.base import Context, ControlData, Controller, Status
from primitives.blackboard import ARM_TWIST
from primitives.filters import ContactWrench
from primitives.robot import Readings

ARRIVAL_TOLERANCE = 0.003  # m: over the target, ready to descend


class Place(Controller):
    """Bring the held object over the target, then descend along -n at VELOCITY until
    ||F|| >= FORCE_THRESHOLD (Eq. 3.4), the wrench tared as the descent starts; the
    primitive ends when the arm stops. Only a contact in that descent is the surface at
    FORCE_THRESHOLD: while the object is brought over, the wrist also reads the hand speeding
    up (5 N for the SDH2 carrying a box, MuJoCo), and a place that ended on it stood 11 cm
    above the table. The bring-over still feels what holds the object up, at
    `carry_threshold` along n: the object hangs below the TCP by as much as it sticks out
    of the hand, which the robot does not know, so the table, or what was put down there
    before, can stand higher than the target's approach height; the object is put down
    there (the Baxter pressed a cup 220 N into the table, a spray can 111 N into a pile for
    104 s, docs/empty-the-box.md). A push from the side is not a surface to put it on.

    Descending more than `max_overshoot` below the target without touching anything is a
    failure: there is no surface where the task said. The hand is turned top-down (its yaw
    kept) as it is brought over, or, not `level`, kept as the grasp holds the object: a jar
    held from the side, its hand turned top-down, swung over and lay on its side 8 cm away
    (docs/open-bottle.md).
    """

    def __init__(self, ctx: Context) -> None:
        super().__init__(ctx)
        p = self.params
        self.target = np.asarray(p["target"], float)
        self.normal = unit(p["surface_normal"])
        self.above = self.target + float(p["approach_height"]) * self.normal
        self.velocity = float(p["velocity"])
        self.threshold = float(p["force_threshold"])
        self.carry_threshold = float(p["carry_threshold"])
        self.overshoot = float(p["max_overshoot"])
        self.max_speed = float(p["max_speed"])
        self.level = bool(p["level"])
        self.contact = ContactWrench(float(p["filter_time"]))
        self.shaper = TwistShaper()

    def start(self, readings: Readings) -> None:
        self.contact.start(readings)
        self.shaper.start(self.ctx.memory.get(ARM_TWIST))
        held = readings.tcp[:3, :3]
        self.rotation = top_down(held) if self.level else held.copy()
        self.descending = False

    def update(self, readings: Readings, dt: float) -> ControlData:
        if self.status is not Status.RUNNING:
            return arm_output(np.zeros(6))
        self.contact.update(readings, dt)
        if self.descending and self.contact.force >= self.threshold:
            self.shaper.stop()
            self.finish(Status.DONE, f"placed: |F| = {self.contact.force:.1f} N >= {self.threshold:g} N")
            return arm_output(np.zeros(6))
        position = readings.tcp[:3, 3]
        w, angle = orientation_twist(self.rotation, readings.tcp[:3, :3])
        if not self.descending:
            up = float(readings.tcp[:3, :3] @ self.contact.value[:3] @ self.normal)
            if up >= self.carry_threshold:
                self.shaper.stop()
                height = float((position - self.target) @ self.normal)
                self.finish(Status.DONE, f"placed on something {height:.3f} m over the target: "
                                         f"{up:.1f} N up >= {self.carry_threshold:g} N")
                return arm_output(np.zeros(6))
            to_go = self.above - position
            if np.linalg.norm(to_go) < ARRIVAL_TOLERANCE and angle < ORIENTATION_TOLERANCE:
                self.descending = True
                self.contact.start(readings)
            return arm_output(self.shaper(np.concatenate([clamp_norm(GAIN * to_go, self.max_speed), w]), dt))
        offset = position - self.target
        height = float(offset @ self.normal)
        if height < -self.overshoot:
            self.shaper.stop()
            self.finish(Status.ERROR, f"no surface within {self.overshoot:g} m below the place target")
            return arm_output(np.zeros(6))
        sideways = offset - height * self.normal
        v = -self.velocity * self.normal - GAIN * sideways
        return arm_output(self.shaper(np.concatenate([v, w]), dt))


class ReleaseRetreat(Controller):
    """Hold still while the hand opens; back away along n at VELOCITY only while the
    fingers press on the surface, i.e. the hand is pushed back: F_z < -FORCE_THRESHOLD
    in the hand frame (Eq. 3.5). It has no goal of its own, so it is done at once and
    the release ends when the hand has opened."""

    def __init__(self, ctx: Context) -> None:
        super().__init__(ctx)
        p = self.params
        self.normal = unit(p["surface_normal"])
        self.velocity = float(p["velocity"])
        self.threshold = float(p["force_threshold"])
        self.contact = ContactWrench(float(p["filter_time"]))

    def start(self, readings: Readings) -> None:
        self.contact.start(readings)
        self.position = readings.tcp[:3, 3].copy()
        self.rotation = readings.tcp[:3, :3].copy()
        self.finish(Status.DONE, "retreats only while the fingers press on the surface")

    def update(self, readings: Readings, dt: float) -> ControlData:
        fz = self.contact.update(readings, dt)[2]
        position = readings.tcp[:3, 3]
        if fz < -self.threshold:
            self.position = position + self.velocity * dt * self.normal
            v = self.velocity * self.normal
        else:
            v = GAIN * (self.position - position)
        w, _ = orientation_twist(self.rotation, readings.tcp[:3, :3])
        return arm_output(np.concatenate([v, w]))

