"""Arm controllers that work against a supporting surface: place (Eq. 3.4) and release
retreat (Eq. 3.5) of thesis 3.3.3 - 3.3.4 (the slide, Eq. 3.6, is `primitives.arm.slide`).

Both read the contact wrench (tared at the state's start, see `ContactWrench`) and
the SURFACE_NORMAL n, a world vector pointing out of the surface: pressing on the
surface makes the contact force point along +n.
"""

from __future__ import annotations

import numpy as np

from atd.model.frames import GRAVITY
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
from primitives.blackboard import ARM_TWIST, LOCATED_ALONG
from primitives.filters import WEIGHED, ContactWrench, held_wrench
from primitives.robot import Readings

ARRIVAL_TOLERANCE = 0.003  # m: over the target, ready to descend


class Place(Controller):
    """Bring the held object over the target, then descend along -n at VELOCITY until
    ||F|| >= FORCE_THRESHOLD (Eq. 3.4), the wrench tared as the descent starts; the
    primitive ends when the arm stops. Only a contact in that descent is the surface at
    FORCE_THRESHOLD: while the object is brought over, the wrist also reads the hand speeding
    up. The bring-over still feels what holds the object up, at `carry_threshold` along n:
    the object hangs below the TCP by an amount the robot does not know, so the table, or
    what was put down there before, can stand higher than the target's approach height, and
    the object is put down there (docs/empty-the-box.md). A push from the side is not a
    surface to put it on.

    The target is for the TCP with the object held at `hand_point`, where the grasp's hand
    shape holds it; a grasp that found the object elsewhere holds it off that point
    (docs/pick-and-place.md). So, over the target, the arm holds still for `weigh_time` and
    the wrist weighs the object: the line its weight hangs on, from the wrist's torque, is
    where the object is, and the arm moves that line over the target before it descends. A
    wrist that cannot tell (`weigh_time` 0), or that feels less than WEIGHED of the object's
    believed weight, leaves the object where the hand shape says, and the place says so. A
    wrist that cannot weigh, after a jaw grasp that looks along its jaws with a range sensor
    (`LOCATED_ALONG`) and did not see the object there, cannot tell: the place fails rather
    than say it put the object on the target (a Baxter's did, the box 3.2-4.0 cm off it).

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
        self.hand_point = np.asarray(p["hand_point"], float)
        self.weigh_time = float(p["weigh_time"])
        self.contact = ContactWrench(float(p["filter_time"]))
        self.shaper = TwistShaper()

    def start(self, readings: Readings) -> None:
        self.contact.start(readings)
        self.shaper.start(self.ctx.memory.get(ARM_TWIST))
        held = readings.tcp[:3, :3]
        self.rotation = top_down(held) if self.level else held.copy()
        self.descending = False
        self.weights: list[np.ndarray] | None = [] if self.weigh_time > 0.0 else None
        self.held_at = "taken to be where the hand shape holds it: this wrist cannot weigh it"
        located = self.ctx.memory.get(LOCATED_ALONG)
        if self.weights is None and located is not None:
            if not located:
                self.finish(Status.ERROR, "cannot tell where the object is in the hand: this wrist cannot weigh it, "
                                          "and the grasp did not see where along the jaws it closed on it")
                return
            self.held_at = ("taken to be where the hand shape holds it: the grasp closed on its middle, "
                            "seen by its range sensor")

    def update(self, readings: Readings, dt: float) -> ControlData:
        if self.status is not Status.RUNNING:
            return arm_output(np.zeros(6))
        self.contact.update(readings, dt)
        if self.descending and self.contact.force >= self.threshold:
            self.shaper.stop()
            self.finish(Status.DONE, f"placed: |F| = {self.contact.force:.1f} N >= {self.threshold:g} N, "
                                     f"the object {self.held_at}")
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
                if self._weighing(readings):
                    return arm_output(self.shaper(np.zeros(6), dt))
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

    def _weighing(self, readings: Readings) -> bool:
        """Over the target: true while the arm holds still weighing the object; once weighed,
        the target moves so that its weight's line comes down on it (the arm goes there first)."""
        if self.weights is None:
            return False
        self.weights.append(held_wrench(self.ctx.info.hand, readings))
        if len(self.weights) * self.ctx.info.control_period < self.weigh_time:
            return True
        load, self.weights = np.mean(self.weights, axis=0), None
        rotation = readings.tcp[:3, :3]
        hangs = self._weight_line(load, rotation)
        if isinstance(hangs, str):
            self.held_at = f"taken to be where the hand shape holds it: {hangs}"
            return True
        believed = rotation @ self.hand_point
        shift = hangs - believed
        shift -= float(shift @ self.normal) * self.normal
        self.target = self.target - shift
        self.above = self.above - shift
        self.held_at = f"weighed {np.linalg.norm(shift) * 100:.1f} cm from where the hand shape holds it"
        return True

    def _weight_line(self, load: np.ndarray, rotation: np.ndarray) -> np.ndarray | str:
        """Where the held load's weight hangs from the TCP (world frame, a point on its line,
        from the wrist's torque about its sensor), or why the wrist cannot say: the task
        gives no weight, or it feels less than WEIGHED of it."""
        force, torque = load[:3], load[3:]
        weight = float(force @ (rotation.T @ np.array([0.0, 0.0, -1.0]))) / GRAVITY  # kg
        known = self.ctx.object.weight if self.ctx.object is not None else None
        if not known:
            return "the task gives no weight to weigh it by"
        if weight < WEIGHED * known:
            return f"the wrist feels {weight * 1000:.0f} g of its {known * 1000:.0f} g"
        point = np.cross(force, torque) / float(force @ force) + self.ctx.info.hand.wrist
        return rotation @ point


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

