"""Arm controllers that work against a supporting surface: place (Eq. 3.4), release
retreat (Eq. 3.5) and slide (Eq. 3.6) of thesis 3.3.3 - 3.3.5.

All three read the contact wrench (tared at the state's start, see `ContactWrench`) and
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
# Slide: m/s of normal motion per N of force error. Small enough that a stiff contact
# (2e5 N/m measured on the Melfa against the table) stays stable at 200 Hz: 5e-4 * 2e5 * 0.005 = 0.5.
FORCE_GAIN = 5e-4
# m the hand may sink below the slide's target height: it presses on the object's top, which
# the target's height gives; sinking further, it has slid off the object, or missed it, and
# presses on whatever is below (the SDH2 straddling a box slid to its target on the table,
# the box unmoved; ours).
SLIDE_DEPTH = 0.01


class Place(Controller):
    """Bring the held object over the target, then descend along -n at VELOCITY until
    ||F|| >= FORCE_THRESHOLD (Eq. 3.4), the wrench tared as the descent starts; the
    primitive ends when the arm stops. Only a contact in that descent is the surface: while
    the object is brought over, the wrist also reads the hand speeding up (5 N for the SDH2
    carrying a box, MuJoCo), and a place that ended on it stood 11 cm above the table.

    Descending more than `max_overshoot` below the target without touching anything is a
    failure: there is no surface where the task said.
    """

    def __init__(self, ctx: Context) -> None:
        super().__init__(ctx)
        p = self.params
        self.target = np.asarray(p["target"], float)
        self.normal = unit(p["surface_normal"])
        self.above = self.target + float(p["approach_height"]) * self.normal
        self.velocity = float(p["velocity"])
        self.threshold = float(p["force_threshold"])
        self.overshoot = float(p["max_overshoot"])
        self.max_speed = float(p["max_speed"])
        self.contact = ContactWrench(float(p["filter_time"]))
        self.shaper = TwistShaper()

    def start(self, readings: Readings) -> None:
        self.contact.start(readings)
        self.shaper.start(self.ctx.memory.get(ARM_TWIST))
        self.rotation = top_down(readings.tcp[:3, :3])
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


class Slide(Controller):
    """Press on the object with a normal force between the two thresholds while moving it
    to the target (Eq. 3.6): too little force, move towards the surface at
    CONTACT_VELOCITY; too much, move away; in between, move along the surface towards the
    target at TARGET_VELOCITY. Done when the TCP is within `tolerance` of the target along
    the surface; an error once it has sunk SLIDE_DEPTH below the target's height, where
    the object's top is not.

    Along the normal the speed is proportional to the force's distance from the band's
    middle, up to CONTACT_VELOCITY, rather than the equation's bang-bang: against a stiff
    contact 5 mm/s for one tick already jumps across the band, and the force would
    chatter from one side to the other without ever letting the tangential motion start.
    """

    def __init__(self, ctx: Context) -> None:
        super().__init__(ctx)
        p = self.params
        self.target = np.asarray(p["target"], float)
        self.normal = unit(p["surface_normal"])
        self.lower = float(p["lower_force_threshold"])
        self.upper = float(p["upper_force_threshold"])
        self.target_velocity = float(p["target_velocity"])
        self.contact_velocity = float(p["contact_velocity"])
        self.tolerance = float(p["tolerance"])
        self.contact = ContactWrench(float(p["filter_time"]))

    def start(self, readings: Readings) -> None:
        self.contact.start(readings)
        self.rotation = readings.tcp[:3, :3].copy()

    def update(self, readings: Readings, dt: float) -> ControlData:
        if self.status is not Status.RUNNING:
            return arm_output(np.zeros(6))
        force = readings.tcp[:3, :3] @ self.contact.update(readings, dt)[:3]
        pressing = float(force @ self.normal)
        error = self.target - readings.tcp[:3, 3]
        sunk = float(error @ self.normal)
        if sunk > SLIDE_DEPTH:
            self.finish(Status.ERROR, f"lost the object: the hand sank {sunk * 100:.1f} cm below the slide's "
                                      f"height looking for a surface to press on")
            return arm_output(np.zeros(6))
        along = error - float(error @ self.normal) * self.normal
        if np.linalg.norm(along) < self.tolerance:
            self.finish(Status.DONE, f"slid to the target, pressing with {pressing:.1f} N")
            return arm_output(np.zeros(6))
        speed = FORCE_GAIN * (pressing - (self.upper + self.lower) / 2)
        v = max(-self.contact_velocity, min(self.contact_velocity, speed)) * self.normal
        if self.lower < pressing < self.upper:
            v = v + clamp_norm(GAIN * along, self.target_velocity)
        w, _ = orientation_twist(self.rotation, readings.tcp[:3, :3])
        return arm_output(np.concatenate([v, w]))
