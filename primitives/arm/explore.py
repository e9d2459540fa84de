"""The explore primitive (thesis Table 3.1): "move the hand towards a specified direction and
stop when a contact is detected", and say where.

It feels a contact as the other guarded motions do: the wrist's contact wrench, tared as it
starts (`ContactWrench`; a press it starts on and moves away from, such as free_one's rise
off what its slides pressed on, or from under what held a finger down, is not felt as it
eases), and the tactile pads, each tared as it starts too (a hand that holds something
reads its grip all along).
"""

from __future__ import annotations

import math

import numpy as np

from primitives.arm.approach_phases import APPROACH_ACCELERATION
from primitives.arm.motion import (GAIN, STALL_TIME, Stall, TwistShaper, clamp_norm, norm, orientation_twist, unit,
                                   what_stops)
from primitives.arm.move import EASE_OFF, arm_output
from primitives.base import Context, ControlData, Controller, Status
from primitives.blackboard import ARM_TWIST
from primitives.filters import ContactWrench, Leaving
from primitives.robot import Readings
from primitives.values import Contact

ARRIVED = 0.001  # m short of max_distance that counts as having gone all the way
SETTLED = 0.0005  # m from the eased-off rest where a touch is over: the next motion tares the wrist there, not mid-impact
SETTLE_LIMIT = 1.0  # s after the touch it is over in any case: an arm that cannot ease off does not hold the task


class Explore(Controller):
    """Move the TCP along `direction` (world frame) at `speed` until the wrist, or a pad, feels
    `force_threshold` more than it did at the start: the contact written to `Context.memory`
    under `writes` (a `Contact`, where the hand's `hand_point` was: the point of its shape
    that leads, so that a later target from it is where the hand touched, whatever the
    hand), then DONE once the hand rests EASE_OFF back from it (a
    motion that began at the touch tared the wrist mid-impact and read its ring as a contact).
    Having gone `max_distance` without one: ERROR, "nothing within D m"; stalled short of it
    without one (`Stall`: a joint at its limit, a singularity): ERROR, saying what stops it. The hand keeps the
    orientation it started with; it speeds up at the robust grasp's gentle
    APPROACH_ACCELERATION (a faster start reads as a contact on the wrist) and slows down
    at it too, so a leg that ends without a contact ends at rest."""

    def __init__(self, ctx: Context) -> None:
        super().__init__(ctx)
        p = self.params
        self.direction = unit(p["direction"])
        self.speed = float(p["speed"])
        self.threshold = float(p["force_threshold"])
        self.max_distance = float(p["max_distance"])
        self.writes = str(p.get("writes", ""))
        self.hand_point = np.asarray(p.get("hand_point", (0.0, 0.0, 0.0)), float)
        self.contact = ContactWrench(float(p["filter_time"]), Leaving(ctx.info.hand, self.threshold,
                                                                         rises=bool(self.direction[2] > 0.0)))
        self.shaper = TwistShaper(acceleration_limits=(APPROACH_ACCELERATION,) * 3 + (0.0,) * 3)
        self.stall = Stall()
        self.found: Contact | None = None
        self.blocked = False  # stopped short without a contact: it cannot say nothing lies further on

    def start(self, readings: Readings) -> None:
        self.contact.start(readings)
        self.shaper.start(self.ctx.memory.get(ARM_TWIST))
        self.pad_bias = readings.pad_force.copy()
        self.origin = readings.tcp[:3, 3].copy()
        self.rotation = readings.tcp[:3, :3].copy()
        self.rest = self.origin
        self.stall.reset(readings.time)
        if self.writes:
            self.ctx.memory.pop(self.writes, None)  # an earlier visit's contact is not this one's

    def felt(self, readings: Readings) -> tuple[str, float] | None:
        """The sensor that feels a contact and its force over the start's, or None: the wrist
        first, then the pads."""
        if self.contact.force >= self.threshold:
            return "wrist", self.contact.force
        if len(self.pad_bias):
            extra = readings.pad_force - self.pad_bias
            pad = int(np.argmax(extra))
            if extra[pad] >= self.threshold:
                return self.ctx.info.hand.pads[pad].name, float(extra[pad])
        return None

    def update(self, readings: Readings, dt: float) -> ControlData:
        position = readings.tcp[:3, 3]
        w, _ = orientation_twist(self.rotation, readings.tcp[:3, :3])
        if self.status is Status.RUNNING and (found := self.found) is not None:
            if norm(self.rest - position) < SETTLED or readings.time - found.time > SETTLE_LIMIT:
                self._report(found)
        elif self.status is Status.RUNNING:
            self.contact.update(readings, dt)
            travelled = float((position - self.origin) @ self.direction)
            felt = self.felt(readings)
            if felt is not None:
                self._touched(readings, felt, travelled)
            elif travelled >= self.max_distance - ARRIVED:
                self.shaper.stop()
                self.rest = position.copy()
                self.finish(Status.ERROR, f"nothing within {self.max_distance:g} m")
            elif self.stall.stalled(self.max_distance - travelled, readings.time):
                self.shaper.stop()
                self.rest, self.blocked = position.copy(), True
                info = self.ctx.info
                self.finish(Status.ERROR, f"no contact, and no progress for {STALL_TIME:g} s "
                                          f"{(self.max_distance - travelled) * 100:.1f} cm short of "
                                          f"{self.max_distance:g} m: "
                                          f"{what_stops(readings.arm_q, info.arm_joints, info.arm_lower, info.arm_upper)}")
            else:
                left = self.max_distance - travelled
                # as gently as it sped up, then P-controlled onto the end: at GAIN alone each leg took
                # 0.6-0.9 s to creep its last centimetres (blind exploration's looks, docs/empty-the-box.md)
                braking = math.sqrt(2.0 * APPROACH_ACCELERATION * max(left - ARRIVED, 0.0))
                along = min(self.speed, max(GAIN * left, braking))
                on_line = self.origin + travelled * self.direction
                v = along * self.direction + GAIN * (on_line - position)
                return arm_output(self.shaper(np.concatenate([clamp_norm(v, self.speed), w]), dt))
        return arm_output(np.concatenate([GAIN * (self.rest - position), w]))

    def _touched(self, readings: Readings, felt: tuple[str, float], travelled: float) -> None:
        sensor, force = felt
        position = readings.tcp[:3, 3]
        self.shaper.stop()
        self.rest = position - EASE_OFF * self.direction  # or the arm goes on pressing on what it met
        touched = position + readings.tcp[:3, :3] @ self.hand_point
        self.found = Contact(touched, sensor, force, self.direction.copy(), readings.time)
        if self.writes:
            self.ctx.memory[self.writes] = self.found
        self.travelled = travelled

    def _report(self, found: Contact) -> None:
        """Eased off what it touched: done, saying where it touched."""
        x, y, z = found.point
        self.finish(Status.DONE, f"contact after {self.travelled * 100:.1f} cm: {found.sensor} {found.force:.1f} N "
                                 f">= {self.threshold:g} N at ({x:.3f}, {y:.3f}, {z:.3f})")
