"""The arm side of the robust grasp (thesis 3.3.1): approach and alignment (Eq. 3.1), the
sliding grasp (Eq. 3.2), and the moves the hand side asks for. Its phases, and the
trials behind each constant, are in docs/robust-grasp.md."""

from __future__ import annotations

import numpy as np

from atd.model.frames import axis_rotation
from primitives.arm.approach_phases import SETTLE, Approaching, Holding, Phase, Shifting
from primitives.arm.motion import (GAIN, ORIENTATION_TOLERANCE, SUPPORT_BAND, WORLD_DOWN, clamp_norm, norm,
                                   orientation_twist, top_down, unit, what_stops)
from primitives.arm.move import arm_output
from primitives.arm.walls import KnownWalls
from primitives.base import Context, ControlData, Controller, Status
from primitives.filters import ContactWrench, contact_across
from primitives.robot import Readings

SHIFT_TOLERANCE = 0.002  # m: a move the hand asked for counts as made this near its goal
SHIFT_TIME = 2.0  # s: a move not made by then is blocked (by the surface or the object); the grasp goes on from there
SURFACE_FILTER = 0.05  # s the surface force is averaged over: a fingertip on the table chatters tick to tick
FROM_SIDE = np.cos(np.radians(45.0))  # a grasp direction pointing down less than this approaches from the side


class RobustGraspApproach(Controller):
    """Approach along GRASP_DIRECTION until the wrist feels a contact, align on it, then
    ride the supporting surface while the fingers close.

    Alignment (Eq. 3.1, hand frame): while in contact, T_y > T_t moves v_x - v_z,
    T_y < -T_t moves -v_x - v_z; out of contact the hand approaches at v_z; contact with
    |T_y| <= T_t ends the alignment, as does covering MAX_DISTANCE without a contact. Before
    the first contact the hand moves at the approach velocity, not the correction one.
    A grasp from above (the grasp direction within `level_within` of the world's vertical)
    first turns the hand level, keeping its yaw: the object stands on a horizontal support,
    so its grasp comes straight down whatever tilt the approach was left with; it starts
    its approach once level and still for SETTLE, its wrist reading taken afresh. A grasp
    from the side does so too, though its hand is already turned: the move before it leaves
    the arm moving, and the approach stopping it at once read the jolt on the wrist (2.1 N,
    over the 2 N contact) as a finger on the object's top off its centre, so the hand moved
    4.5 cm across a jar it had not touched and never closed on it (examples/open_bottle.xml,
    seed 4; docs/open-bottle.md).
    A first contact above the support and off the grasp centre (placed from the wrist's
    force and torque at the fingertips' depth) is a finger on the object's top: the hand
    rises off it, moves its grasp centre over it, settles and approaches again.
    Sliding grasp (Eq. 3.2): the surface pushes back on the hand with F_s (against the
    grasp direction, measured against the free hand and filtered over SURFACE_FILTER);
    F_s above the contact the slide keeps (F_t) by F_t backs off until F_s is down to F_t
    (and no further than `max_back_off` above where the slide began), telling the hand
    (`pressing`) to hold its fingers meanwhile; F_s down to zero moves forward (unless
    `follow_surface` is off); it ends when the fingers stop. Once they have, the arm holds
    its place, still backing off while the squeeze presses the fingertips on the surface.
    A shift the hand asks for before it has preshaped (rising to free a preshape blocked
    on the table) ends in settling and approaching again, not in the slide.
    In a container the task knows (`KnownWalls`, as the parallel jaws' grasp), every move
    keeps the open hand inside its walls by the hand's `hand_extent` about its footprint's
    middle (`hand_offset`), a start too near a wall first moving the hand in (ACROSS), and its
    floor is the support. There it always settles before its approach, as after that move in:
    the switch onto the grasp jolts the wrist (the SDH2's: 5 N for a tick), and read as a
    finger on a top it moved the hand 5 cm off what vision aimed at (docs/empty-the-box.md).
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
        self.walls = KnownWalls.of(ctx)
        self.contact = ContactWrench(float(p["filter_time"]))
        self.surface = ContactWrench(SURFACE_FILTER)
        self.side = np.array([1.0, 0.0, 0.0])  # v_x of Eq. 3.1

    def start(self, readings: Readings) -> None:
        self.contact.start(readings)
        self.surface.start(readings)
        self.backing = False  # backing off a surface the fingertips press on
        rotation = readings.tcp[:3, :3]
        from_above = float((rotation @ self.direction) @ WORLD_DOWN) >= np.cos(self.level_within)
        self.from_side = float((rotation @ self.direction) @ WORLD_DOWN) < FROM_SIDE  # no fingertip below its TCP
        self.rotation = top_down(rotation) if from_above and self.level_within > 0.0 else rotation.copy()
        _, tilt = orientation_twist(self.rotation, rotation)
        # a level hand from above starts at once; one from the side, or over a known box, first stands still
        # (class docstring)
        settle = tilt >= ORIENTATION_TOLERANCE or self.from_side or bool(self.walls.containers)
        self.phase = Phase.SETTLE if settle else Phase.APPROACH
        position = readings.tcp[:3, 3]
        inside = self.walls.inside(self.rotation, position)
        if norm(inside - position) >= SHIFT_TOLERANCE:  # the open hand would come down on a wall
            self.route, self.phase = [inside], Phase.ACROSS
        self.approaching = Approaching(readings.tcp[:3, 3].copy())
        self.still = 0.0  # s the hand has been still: settling, or at a raise's goal (SETTLE)
        # m: the raise or lower being made. Kept across holds, as the still time is across
        # phases: a raise the hand gave up on (dropped while lifting) and asks for again is
        # not made again; docs/robust-grasp.md, "Known quirks".
        self.weighing: float | None = None
        self.moves = 0  # moves across a contact made so far
        self.ctx.blackboard.contact = False

    def update(self, readings: Readings, dt: float) -> ControlData:
        """One tick: the phases in `Phase`'s order, each only while it is the phase."""
        board = self.ctx.blackboard
        wrench = self.contact.update(readings, dt)
        pushed = -float(self.surface.update(readings, dt)[:3] @ self.direction)  # F_s
        rotation, position = readings.tcp[:3, :3], readings.tcp[:3, 3]
        if board.shift is not None and self.phase is not Phase.SHIFT:
            self._begin_shift(readings)
        v = np.zeros(3)  # hand frame
        if self.phase is Phase.APPROACH and board.preshaped:
            v = self._approach(readings, wrench, dt)
        self._back_off(position, rotation, pushed)
        if self.phase is Phase.SLIDE:
            v = self._slide(position, pushed)
        w, angle = orientation_twist(self.rotation, rotation)
        if self.phase is Phase.HOLD:
            self._hold(readings, dt)
        if self.phase is Phase.SETTLE:
            self._settle(readings, angle, dt)
        world = rotation @ v
        if self.phase is Phase.ACROSS:
            world = self._across(readings)
        if self.phase is Phase.HOLD:
            world = GAIN * (self.holding.goal - position)
        if self.phase is Phase.SHIFT:
            world = GAIN * (self.shifting.goal - position)
            self._shift(readings, angle)
        return arm_output(np.concatenate([world, w]))

    # -- phases ---------------------------------------------------------------------------
    def _approach(self, readings: Readings, wrench: np.ndarray, dt: float) -> np.ndarray:
        """Eq. 3.1 (hand frame); on to the sliding grasp once the alignment is over, or
        across a contact on the object's top."""
        if self.contact.force >= self.force_threshold:
            self.approaching.stall.reset(readings.time)  # aligning on a contact is progress of its own
            if self._over_contact(readings, wrench):
                return np.zeros(3)
            torque = float(wrench[4])
            if torque > self.torque_threshold:
                return self.speed * (self.side - self.direction)
            if torque < -self.torque_threshold:
                return self.speed * (-self.side - self.direction)
            self._begin_slide(readings)
            return np.zeros(3)
        travelled = self.approaching.travelled(readings, self.direction)
        if travelled >= self.max_distance:
            self._begin_slide(readings)
            return np.zeros(3)
        approaching = self.approaching
        if approaching.stall.stalled(self.max_distance - travelled, readings.time):
            info = self.ctx.info
            self.finish(Status.ERROR, f"the approach made no progress for {approaching.stall.patience:g} s, {travelled * 100:.1f} cm "
                                      f"along, without a contact: "
                                      f"{what_stops(readings.arm_q, info.arm_joints, info.arm_lower, info.arm_upper)}")
            self.phase, self.holding = Phase.HOLD, Holding(readings.tcp[:3, 3].copy())
            return np.zeros(3)
        return approaching.velocity(self.direction, self.approach_speed, dt)

    def _slide(self, position: np.ndarray, pushed: float) -> np.ndarray:
        """Eq. 3.2 (hand frame): back off while pressing, follow a surface lost; hold once the fingers have stopped."""
        if self.ctx.blackboard.fingers_stopped:
            self.phase, self.holding = Phase.HOLD, Holding(position.copy())
            self.finish(Status.DONE, "the fingers closed")
        elif self.backing:
            return -self.backoff_speed * self.direction
        elif pushed <= 0.0 and self.follow_surface:
            return self.speed * self.direction
        return np.zeros(3)

    def _hold(self, readings: Readings, dt: float) -> None:
        """Stay, backing off while the squeeze presses the fingertips on the surface; make
        a raise or lower the hand asks for (`weigh`): the goal moves once, then the arm holds
        still there for SETTLE before it says it is done."""
        holding, board = self.holding, self.ctx.blackboard
        if self.backing:
            holding.goal = holding.goal - self.backoff_speed * dt * (readings.tcp[:3, :3] @ self.direction)
        if board.weigh is None:
            return
        height = board.weigh
        if self.weighing != height:
            self.weighing, self.still = height, 0.0
            holding.goal = holding.goal + height * np.array([0.0, 0.0, 1.0])
        arrived = np.linalg.norm(holding.goal - readings.tcp[:3, 3]) < SHIFT_TOLERANCE
        self.still = self.still + dt if arrived else 0.0
        if self.still >= SETTLE:
            board.weigh = None
            self.weighing = None

    def _settle(self, readings: Readings, angle: float, dt: float) -> None:
        """Turning level, or stopped after a move: approach (again) once level, preshaped and still for SETTLE."""
        ready = angle < ORIENTATION_TOLERANCE and self.ctx.blackboard.preshaped
        self.still = self.still + dt if ready else 0.0
        if self.still >= SETTLE:
            self.contact.start(readings)  # the wrist's reading is the free hand's
            self.surface.start(readings)
            self.approaching = Approaching(readings.tcp[:3, 3].copy())
            self.phase = Phase.APPROACH

    def _across(self, readings: Readings) -> np.ndarray:
        """One tick of the moves over a contact (world frame); settle once they are made."""
        position = readings.tcp[:3, 3]
        if norm(self.route[0] - position) < SHIFT_TOLERANCE:
            self.route.pop(0)
            if not self.route:
                self.phase, self.still = Phase.SETTLE, 0.0
                return np.zeros(3)
        return clamp_norm(GAIN * (self.route[0] - position), self.approach_speed)

    def _shift(self, readings: Readings, angle: float) -> None:
        """The hand's move is made, or as far as the surface or the object allows: slide,
        or (risen to free the preshape) settle and approach again."""
        shifting, board = self.shifting, self.ctx.blackboard
        made = np.linalg.norm(shifting.goal - readings.tcp[:3, 3]) < SHIFT_TOLERANCE and angle < ORIENTATION_TOLERANCE
        probed = shifting.probing and self.contact.force >= self.force_threshold
        if made or probed or readings.time - shifting.started > SHIFT_TIME:
            board.shift = None
            if board.preshaped:
                self._begin_slide(readings)
            else:
                self.phase, self.still = Phase.SETTLE, 0.0

    # -- transitions ----------------------------------------------------------------------
    def _begin_shift(self, readings: Readings) -> None:
        """The hand asks for a move (`Shift`: hand-frame m and a turn about the approach axis)."""
        request = self.ctx.blackboard.shift
        shift, turn = request.offset, request.turn
        rotation, position = readings.tcp[:3, :3], readings.tcp[:3, 3]
        self.rotation = self.rotation @ axis_rotation(self.direction, turn)
        # A shift along the approach looks for the object, so a contact ends it; a
        # sideways one drags the fingertips over the surface, which is no reason to stop.
        goal = self.walls.inside(self.rotation, position + rotation @ shift)
        self.shifting = Shifting(goal, float(shift @ self.direction) > 0.0, readings.time)
        self.phase = Phase.SHIFT
        self.contact.start(readings)

    def _over_contact(self, readings: Readings, wrench: np.ndarray) -> bool:
        """A first contact above the support and off the grasp centre across the hand is a
        finger on the object's top: rise off it and move the grasp centre over it (up to
        `max_shifts` times); true if that is what happens. Left there, the finger pushed
        the object over as the fingers closed."""
        rotation, position = readings.tcp[:3, :3], readings.tcp[:3, 3]
        # fingertips on the table (or a known box's floor) say nothing
        on_support = not self.from_side and \
            float(position[2]) - self.reach - self.walls.support(position) < SUPPORT_BAND
        if self.moves >= self.max_shifts or on_support:
            return False
        across = contact_across(wrench, self.contact_depth)
        if across is None or norm(across - self.grasp_centre) <= self.centre_band:
            return False
        self.moves += 1
        up = position - self.clearance * (rotation @ self.direction)
        self.route = [up, self.walls.inside(self.rotation, up + rotation @ clamp_norm(across - self.grasp_centre,
                                                                                      self.max_shift))]
        self.phase = Phase.ACROSS
        return True

    def _back_off(self, position: np.ndarray, rotation: np.ndarray, pushed: float) -> None:
        """Backing off starts at F_t over the contact the slide keeps and goes on down to it,
        no further than `max_back_off` above where the slide began; the hand is told while sliding."""
        self.backing = pushed >= 2.0 * self.force_threshold or (self.backing and pushed > self.force_threshold)
        risen = float((self.slid_from - position) @ (rotation @ self.direction)) if self.phase is Phase.SLIDE else 0.0
        self.backing = self.backing and risen < self.max_back_off
        self.ctx.blackboard.pressing = self.backing and self.phase is Phase.SLIDE

    def _begin_slide(self, readings: Readings) -> None:
        self.phase = Phase.SLIDE
        self.slid_from = readings.tcp[:3, 3].copy()
        self.ctx.blackboard.contact = True
