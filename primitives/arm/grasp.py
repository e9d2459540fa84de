"""The arm side of the grasps: the robust grasp (thesis 3.3.1) with its approach and
alignment (Eq. 3.1), sliding grasp (Eq. 3.2) and the moves the hand side asks for
(finger-lost correction); and the naive baseline grasp of thesis 3.4.1.

Both talk with the hand side through the blackboard: they raise CONTACT when the hand may
close; the robust one also watches FINGERS_STOPPED to end the sliding grasp and carries
out SHIFT requests.
"""

from __future__ import annotations

import numpy as np

from atd.model.frames import axis_rotation
from primitives.arm.motion import (GAIN, ORIENTATION_TOLERANCE, SUPPORT_BAND, WORLD_DOWN, clamp_norm, norm,
                                   orientation_twist, top_down, unit)
from primitives.arm.move import arm_output
from primitives.base import Context, ControlData, Controller, Status
from primitives.blackboard import CONTACT, FINGERS_STOPPED, PRESHAPED, PRESSING, SHIFT, WEIGH
from primitives.filters import ContactWrench, contact_across
from primitives.robot import Readings

SHIFT_TOLERANCE = 0.002  # m: a requested shift counts as made
BACK_OFF = 0.002  # m: the naive approach settles this far short of its contact
SHIFT_TIME = 2.0  # s: a shift that has not arrived by then is blocked; the grasp goes on from there
# s the sliding grasp averages the surface force over: a PyBullet fingertip on the table reads
# 17 N and 0 N on alternate 5 ms ticks, and a bang-bang slide on each tick's reading drives
# that chatter instead of riding the surface (SDH2 pinch, grasp_and_lift, seed 0).
SURFACE_FILTER = 0.05
# m/s^2 the approach speeds up at: a hand set moving at 3 cm/s within one 5 ms tick read 2.2 N on
# the Barrett's wrist, over the 2 N contact threshold, and the approach ended where it began,
# 2 cm above the object's top (MuJoCo, grasp_and_lift with the seeds' approach error)
APPROACH_ACCELERATION = 0.3
# s the hand stays still once level, or once over a contact, before the wrist's reading is taken
# as the free hand's: the turn's own jolt read 5.9 N on the Barrett's wrist (MuJoCo), and the
# weight of a hand turned by 3 degrees another 1.3 N, so the approach took that for a contact and
# the fingers closed 2 cm above the table beside the object (the preset, approach error, cylinder
# trial 1); stopping at the end of the moves over a contact read 2.2-2.4 N on the SDH2's, and
# the fingers closed 5-9 cm above the object (MuJoCo, the preset's cylinder 4, wood 9, speaker 7)
SETTLE = 0.1


class RobustGraspApproach(Controller):
    """Approach along GRASP_DIRECTION until the wrist feels a contact, align on it, then
    ride the supporting surface while the fingers close.

    Alignment (Eq. 3.1, hand frame): while in contact, T_y > T_t moves v_x - v_z,
    T_y < -T_t moves -v_x - v_z; out of contact the hand approaches at v_z; contact with
    |T_y| <= T_t ends the alignment, as does covering MAX_DISTANCE without a contact. Before
    the first contact the hand moves at the approach velocity, not the correction one.
    A grasp from above (the grasp direction within `level_within` of the world's vertical)
    first turns the hand level, keeping its yaw: the object stands on a horizontal support,
    so its grasp comes straight down whatever tilt the approach was left with, and the robot
    knows which way is down. Left tilted, one fingertip lands on the table first, waits
    there while the others close, and they push the object away (rotation-only approach
    error, MuJoCo, 30 trials per hand: Barrett 2 lifted, SDH2 7; levelled: 18 and 15).
    A hand that has to turn level starts its approach once it is level and has been still
    for SETTLE, its wrist reading taken afresh: the turn changes how the hand's weight
    loads the sensor.
    A first contact above the support and off the grasp centre (placed from the wrist's
    force and torque at the fingertips' depth) is a finger on the object's top: the hand
    rises off it, moves its grasp centre over it and approaches again (Eq. 3.1's idea,
    across both of the hand's axes; its torque threshold is for the thesis' sensor, and
    a fingertip's 2-17 N at 5-10 cm stays under it); it stays still for SETTLE before it
    approaches again, as after turning level.
    Sliding grasp (Eq. 3.2): the surface pushes back on the hand with F_s (against the
    grasp direction, measured against the free hand of the state's start and filtered over
    SURFACE_FILTER); the approach ended on F_s = F_t, the contact the slide keeps: F_s
    above it by F_t (fingers pushing on the surface) backs off, at the back-off velocity,
    until F_s is down to F_t again (and no further than `max_back_off` above where the slide
    began: unbounded, it rode the SDH2 up 4 cm in 5 s while its fingers stood jammed on a
    steel weight, until they closed over its top), F_s down to zero (the contact lost)
    moves forward (unless `follow_surface` is off), otherwise the arm stays; it ends when
    the fingers stop.
    While it backs off it tells the hand (PRESSING) to hold its fingers: closing
    fingertips swing down onto the surface faster than CORRECTION_VELOCITY lifts them, and
    jammed there they stall on the table short of the object (SDH2 pinch, PyBullet: 30-50 N
    per tip). Once the fingers have closed the arm holds its place, still backing off while
    the squeeze presses the fingertips on the surface: left pressing there, they would spring
    off it as the lift starts, and a guarded lift would read that as meeting resistance.
    A shift the hand asks for before it has preshaped (rising to free a preshape blocked
    on the table) ends in settling and approaching again, not in the slide.
    """

    def __init__(self, ctx: Context) -> None:
        super().__init__(ctx)
        p = self.params
        self.direction = unit(p["grasp_direction"])
        self.max_distance = float(p["max_distance"])
        self.force_threshold = float(p["force_threshold"])
        self.torque_threshold = float(p["torque_threshold"])
        self.level_within = np.radians(float(p["level_within"]))
        self.speed = float(p["correction_velocity"])
        self.approach_speed = float(p["approach_velocity"])
        self.backoff_speed = float(p["backoff_velocity"])
        self.follow_surface = bool(p["follow_surface"])
        self.centre_band = float(p["centre_band"])
        self.max_shift = float(p["max_shift"])
        self.max_shifts = int(p["max_shifts"])
        self.clearance = float(p["clearance"])
        self.reach = float(p["fingertip_reach"])
        self.contact_depth = float(p["wrist_to_tcp"]) + self.reach  # from the wrist sensor to the fingertips
        self.grasp_centre = np.array([*np.asarray(p["grasp_centre"], float)[:2], 0.0])
        self.max_back_off = float(p["max_back_off"])
        self.contact = ContactWrench(float(p["filter_time"]))
        self.surface = ContactWrench(SURFACE_FILTER)
        self.side = np.array([1.0, 0.0, 0.0])  # v_x of Eq. 3.1

    def start(self, readings: Readings) -> None:
        self.contact.start(readings)
        self.surface.start(readings)
        self.backing = False  # backing off a surface the fingertips press on
        self.origin = readings.tcp[:3, 3].copy()
        rotation = readings.tcp[:3, :3]
        from_above = float((rotation @ self.direction) @ WORLD_DOWN) >= np.cos(self.level_within)
        self.rotation = top_down(rotation) if from_above and self.level_within > 0.0 else rotation.copy()
        _, tilt = orientation_twist(self.rotation, rotation)
        self.phase = "settle" if tilt >= ORIENTATION_TOLERANCE else "approach"  # a level hand starts at once
        self.still = 0.0  # s the hand has been level and still
        self.approach_now = 0.0  # m/s: the approach's speed, rising to the approach velocity
        self.goal: np.ndarray | None = None  # where to stay, or to shift to
        self.route: list[np.ndarray] = []  # the moves over a finger's contact, world frame
        self.moves = 0  # moves across made so far
        self.weighing: float | None = None  # the hand's raise or lower being made
        self.ctx.blackboard[CONTACT] = False

    def update(self, readings: Readings, dt: float) -> ControlData:
        board = self.ctx.blackboard
        wrench = self.contact.update(readings, dt)
        rotation, position = readings.tcp[:3, :3], readings.tcp[:3, 3]
        if board.get(SHIFT) is not None and self.phase != "shift":
            shift, turn = np.asarray(board[SHIFT][:3], float), float(board[SHIFT][3])
            self.phase, self.goal = "shift", position + rotation @ shift
            self.rotation = self.rotation @ axis_rotation(self.direction, turn)
            # A shift along the approach looks for the object, so a contact ends it; a
            # sideways one drags the fingertips over the surface, which is no reason to stop.
            self.probing = float(shift @ self.direction) > 0.0
            self.contact.start(readings)
            self.shift_started = readings.time
        v = np.zeros(3)  # hand frame
        if self.phase == "approach" and board.get(PRESHAPED, True):
            v = self._align(readings, wrench, dt)
        pushed = -float(self.surface.update(readings, dt)[:3] @ self.direction)  # F_s
        # Backing off starts at F_t over the contact the slide keeps and goes on down to it.
        self.backing = pushed >= 2.0 * self.force_threshold or (self.backing and pushed > self.force_threshold)
        risen = float((self.slid_from - position) @ (rotation @ self.direction)) if self.phase == "slide" else 0.0
        self.backing = self.backing and risen < self.max_back_off
        board[PRESSING] = self.backing and self.phase == "slide"
        if self.phase == "slide":
            if board.get(FINGERS_STOPPED):
                self.phase, self.goal = "hold", position.copy()
                self.finish(Status.DONE, "the fingers closed")
            elif self.backing:
                v = -self.backoff_speed * self.direction
            elif pushed <= 0.0 and self.follow_surface:
                v = self.speed * self.direction
        if self.phase == "hold" and self.backing:  # squeezing presses the tips down
            self.goal = self.goal - self.backoff_speed * dt * (rotation @ self.direction)
        if self.phase == "hold" and board.get(WEIGH) is not None:
            self._weigh(readings, float(board[WEIGH]), dt)
        w, angle = orientation_twist(self.rotation, rotation)
        if self.phase == "settle":  # turning level, or stopped after the moves over a contact
            self.still = self.still + dt if angle < ORIENTATION_TOLERANCE and board.get(PRESHAPED, True) else 0.0
            if self.still >= SETTLE:
                self._approach_from(readings)
        world = rotation @ v
        if self.phase == "across":
            world = self._across(readings)
        if self.phase in ("hold", "shift"):
            world = GAIN * (self.goal - position)
            made = np.linalg.norm(self.goal - position) < SHIFT_TOLERANCE and angle < ORIENTATION_TOLERANCE
            if self.phase == "shift" and (made or (self.probing and self.contact.force >= self.force_threshold)
                                          or readings.time - self.shift_started > SHIFT_TIME):
                board[SHIFT] = None  # made, or as far as the surface or the object allows
                if board.get(PRESHAPED, True):
                    self._slide(readings)
                else:  # risen to free the preshape: approach again once it is made and the hand still
                    self.phase, self.still = "settle", 0.0
        return arm_output(np.concatenate([world, w]))

    def _weigh(self, readings: Readings, height: float, dt: float) -> None:
        """The hand's request to raise (or lower) what it holds by `height`: the goal moves
        once, then the arm holds still there for SETTLE before it says it is done."""
        if self.weighing != height:
            self.weighing, self.still = height, 0.0
            self.goal = self.goal + height * np.array([0.0, 0.0, 1.0])
        arrived = np.linalg.norm(self.goal - readings.tcp[:3, 3]) < SHIFT_TOLERANCE
        self.still = self.still + dt if arrived else 0.0
        if self.still >= SETTLE:
            self.ctx.blackboard[WEIGH] = None
            self.weighing = None

    def _approach_from(self, readings: Readings) -> None:
        """Start (again) an approach, the wrist's reading taken as the free hand's."""
        self.contact.start(readings)
        self.surface.start(readings)
        self.origin = readings.tcp[:3, 3].copy()
        self.approach_now = 0.0
        self.phase = "approach"

    def _over_contact(self, readings: Readings, wrench: np.ndarray) -> bool:
        """A first contact above the support and off the grasp centre across the hand is a
        finger on the object's top: rise off it, move the grasp centre over it, approach
        again (up to `max_shifts` times). True if that is what happens. Left there, the
        finger pushed the object over as the fingers closed (SDH2, MuJoCo, the preset's mug
        trial 0: the pinch 5.6 cm off the mug along its line, the preshape's descent stopped
        on the mug at 17 N)."""
        rotation, position = readings.tcp[:3, :3], readings.tcp[:3, 3]
        on_support = float(position[2]) - self.reach < SUPPORT_BAND  # the fingertips on the table say nothing
        if self.moves >= self.max_shifts or on_support:
            return False
        across = contact_across(wrench, self.contact_depth)
        if across is None or norm(across - self.grasp_centre) <= self.centre_band:
            return False
        self.moves += 1
        up = position - self.clearance * (rotation @ self.direction)
        self.route = [up, up + rotation @ clamp_norm(across - self.grasp_centre, self.max_shift)]
        self.phase = "across"
        return True

    def _across(self, readings: Readings) -> np.ndarray:
        """One tick of the moves over a contact; the approach starts again once they are made."""
        position = readings.tcp[:3, 3]
        if norm(self.route[0] - position) < SHIFT_TOLERANCE:
            self.route.pop(0)
            if not self.route:  # settle first: stopping read up to 2.4 N on the wrist
                self.phase, self.still = "settle", 0.0
                return np.zeros(3)
        return clamp_norm(GAIN * (self.route[0] - position), self.approach_speed)

    def _align(self, readings: Readings, wrench: np.ndarray, dt: float) -> np.ndarray:
        """Eq. 3.1; switches to the sliding grasp when the alignment is over."""
        if self.contact.force >= self.force_threshold:
            if self._over_contact(readings, wrench):
                return np.zeros(3)
            torque = float(wrench[4])
            if torque > self.torque_threshold:
                return self.speed * (self.side - self.direction)
            if torque < -self.torque_threshold:
                return self.speed * (-self.side - self.direction)
            self._slide(readings)
            return np.zeros(3)
        travelled = float((readings.tcp[:3, 3] - self.origin) @ (readings.tcp[:3, :3] @ self.direction))
        if travelled >= self.max_distance:
            self._slide(readings)
            return np.zeros(3)
        self.approach_now = min(self.approach_speed, self.approach_now + APPROACH_ACCELERATION * dt)
        return self.approach_now * self.direction

    def _slide(self, readings: Readings) -> None:
        self.phase = "slide"
        self.slid_from = readings.tcp[:3, 3].copy()
        self.ctx.blackboard[CONTACT] = True


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
        self.ctx.blackboard[CONTACT] = False

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
        self.ctx.blackboard[CONTACT] = True
        self.finish(Status.DONE, reason)
