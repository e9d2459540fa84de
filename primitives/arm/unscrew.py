"""The arm side of the unscrew (thesis 3.3.6, Fig. 3.11): hold while the fingers pinch the
cap, twist it TWIST_ANGLE about the approach axis through the grasp centre, pull back to
test whether it is free; a twist above UNSCREW_TORQUE_LIMIT, a pull above PULL_FORCE_LIMIT,
or fingers closed on nothing send the arm back to its start pose to pinch again, moved
onto the cap's axis by the reactive alignment (Fig. 3.12) unless it is switched off. The
cap is off when a pull has gone CAP_REMOVED_DISTANCE with the pads still pressing it:
what the wrist and the pads say, never where the simulator has the cap. A cap the pads
held and twisted, and then close on nothing where they held it, has left its thread and
the pads (a pinch off its axis squeezes a freed cap out): the unscrew ends saying so, not
pinching on after a cap that is gone; not on jaws without tactile pads, whose grip on a
chord of a cap off their line slides off a cap still on its thread, nor on jaws pinching
from the cap's top (`_lost_where_held`). Pinches spent, the unscrew says what it felt: the
cap not felt to come off, and why the last one ended. Its phases are in
`primitives.arm.unscrew_phases`; docs/writing-a-primitive.md draws the machine.

A gripper's jaws have little room around a cap (the Melfa's 4 mm a side around a 60 mm
cap), so an approach off the cap's axis lands a jaw on its top, and the guarded descent
around the cap stops short there. With the alignment the unscrew then seats the jaws
first (SEAT, ACROSS), as the robust jaw grasp looks for an object its jaws missed
(`primitives.arm.jaw_grasp`): off the top, across to the next point of a search along
the jaws' line, their room around the cap apart, and down again to where the descent was
going, until the jaws get there."""

from __future__ import annotations

import numpy as np

from atd.model.frames import axis_rotation
from primitives.arm.jaw_grasp import STALL_CONTACT
from primitives.arm.motion import GAIN, ORIENTATION_TOLERANCE, clamp_norm, norm, orientation_twist, unit
from primitives.arm.move import arm_output
from primitives.arm.unscrew_phases import Phase, Pulling, Seating, Tally, TcpPose, Twisting
from primitives.base import Context, ControlData, Controller, Status
from primitives.blackboard import SHORT_OF_TARGET, CapGrip
from primitives.filters import ContactWrench, held_wrench
from primitives.hands.parallel_jaw import TOUCH
from primitives.robot import Readings
from primitives.search import search_offsets

TWIST_SPEED = 0.5  # rad/s: a 30 degree twist in about a second, slow beside the pads' force loop
PULL_SPEED = 0.02  # m/s: the 40 mm pull in 2 s; a threaded cap reaches the 7 N limit within millimetres
RETURN_SPEED = 0.05  # m/s: back to the start pose with the fingers open, clear of the cap
ARRIVED = 0.002  # m: the start pose counts as reached this near (the robust grasp's SHIFT_TOLERANCE)
ALIGN_TOLERANCE = 0.002  # m: the pads place the axis to half a 3 mm taxel row; a finer move chased that rounding
MOTOR_ALIGN_TOLERANCE = 0.0005  # m: motor jaws' middle is their joint's, exact; 1.7 mm off, open paddles rubbed the cap
PINCH_TIME = 6.0  # s: closing from the preshape (up to 1.5 s) and the robust grasp's SETTLE_LIMIT to reach the force
TWIST_TURNS = 3.0  # times a twist's time at TWIST_SPEED: not turned by then, the cap turns about another axis
MAX_ALIGN = 0.02  # m: the largest move onto the cap's axis: further, the pads felt more than the cap
WRIST_MARGIN = np.radians(5.0)  # rad a twist stays short of the wrist joint's limit: the servo overshoots near it
MIN_TWIST = np.radians(5.0)  # rad: a wrist with less room than this left turns the cap nowhere
SEAT_SHORT = 0.005  # m: a descent stopped further short met something on the way (pads 5 mm higher still grip a cap)
SEAT_SPEED = 0.02  # m/s: down onto the cap, slow enough to stop on a jaw on its top before pressing it hard
SEAT_RISE = 0.005  # m up off the cap's top before moving across: the jaw stopped within a millimetre of it
ACROSS_ARRIVED = 0.0005  # m: the move across ends this near its end; at ARRIVED a jaw came down on the cap's rim
SEARCH_STEP = 1.0 / 3.0  # of the jaws' room around the cap: a step that cannot jump over the band where they fit
SEARCH_POINTS = 14  # moves across, to either side in turn: 7 steps each way (Melfa 19 mm), then pinch
OUTSIDE_SPEED = 0.01  # m/s the arm yields to a jaw pressing the cap from outside: slow beside the jaws' closing


class UnscrewArm(Controller):
    """The unscrew's arm: a phase machine (`Phase`, one method each) driven by the wrist's
    force and torque and by what the hand says of the cap (`Blackboard.cap`)."""

    def __init__(self, ctx: Context) -> None:
        super().__init__(ctx)
        p = self.params
        self.direction = unit(p["grasp_direction"])
        self.twist_angle = np.radians(float(p["twist_angle"]))
        self.torque_limit = float(p["torque_limit"])
        self.pull_force_limit = float(p["pull_force_limit"])
        self.cap_removed_distance = float(p["cap_removed_distance"])
        self.alignment = bool(p["alignment"])
        self.max_pinches = int(p["max_pinches"])
        self.grasp_centre = np.asarray(p["grasp_centre"], float)
        self.wrist_turn = float(p["wrist_turn"])
        self.wrench = ContactWrench(float(p["filter_time"]))
        self.cap_width = float(p["cap_width"])
        self.threshold = float(p["force_threshold"])

    def start(self, readings: Readings) -> None:
        self.wrench.start(readings)
        self.start_pose = TcpPose(readings.tcp[:3, 3].copy(), readings.tcp[:3, :3].copy())
        self.still = TcpPose(self.start_pose.position, self.start_pose.rotation)  # where a still phase holds
        self.tally = Tally(pinches=1)
        self.held = False  # the pads pinched the cap and twisted it from this start pose (or the alignment's move onto it)
        short = self.ctx.memory.pop(SHORT_OF_TARGET, None)
        down = 0.0 if short is None else float(np.asarray(short) @ (self.start_pose.rotation @ self.direction))
        self.room = self._jaws_room(readings)
        along = self.start_pose.rotation @ self.direction
        self.depth = self.start_pose.position + down * along  # where the guarded descent was sending the TCP
        if self.alignment and down > SEAT_SHORT and self.room > 0.0:
            goal = self.depth
            self.seating = Seating(goal, goal, [self.start_pose.position - SEAT_RISE * along])
            self._hold_here(readings, Phase.ACROSS)  # off the top first: the wrist still rings with the stop on it
            self.ctx.blackboard.contact = False  # the jaws wait open
        else:
            self._pinch_from(readings)

    def update(self, readings: Readings, dt: float) -> ControlData:
        self.wrench.update(readings, dt)
        return arm_output(getattr(self, self.phase.value)(readings, dt))

    @property
    def cap(self) -> CapGrip:
        """What the hand last said of the cap; before it has said anything, an empty grip."""
        return self.ctx.blackboard.cap or CapGrip()

    # -- phases: one tick each, returning the TCP twist (world frame) ---------------------
    def _seat(self, readings: Readings, dt: float) -> np.ndarray:
        """Down along the approach, the jaws open, to where the guarded descent was going:
        there, pinch; a contact on the way (felt, or pressing while the arm stalls) is a jaw
        on the cap's top."""
        seating = self.seating
        left = norm(seating.goal - readings.tcp[:3, 3])
        stalled = seating.stall.stalled(left, readings.time) and self.wrench.force >= STALL_CONTACT * self.threshold
        if left < ARRIVED:
            self._pinch_from(readings)
        elif self.wrench.force >= self.threshold or stalled:
            self._jaw_on_top(readings)
        goal = seating.goal if self.phase is Phase.SEAT else self.still.position
        return self._toward(readings, TcpPose(goal, self.start_pose.rotation), SEAT_SPEED)

    def _across(self, readings: Readings, dt: float) -> np.ndarray:
        """Up off the cap's top, then across, the wrist watched as the seat's descent watches
        it: a jaw that meets the cap on the way across is on it again (`_jaw_on_top`), not
        pushed on into it; then down again."""
        seating = self.seating
        route = seating.route
        if seating.watched and self.wrench.force >= self.threshold:
            self._jaw_on_top(readings)
            return self._toward(readings, self.still, RETURN_SPEED)
        if norm(route[0] - readings.tcp[:3, 3]) < (ACROSS_ARRIVED if len(route) == 1 else ARRIVED):
            route.pop(0)
            if not route:
                self._begin_seat(readings, seating)
                return self._toward(readings, self.still, RETURN_SPEED)
            self.wrench.start(readings)  # off the top, in free air
            seating.watched = True
        return self._toward(readings, TcpPose(route[0], self.start_pose.rotation), RETURN_SPEED)

    def _pinch(self, readings: Readings, dt: float) -> np.ndarray:
        """At the start pose until the hand has pinched the cap (twist), or closed on nothing,
        or not reached the grasp force on every pad within PINCH_TIME (again). A gripper
        whose one pad touches first asks to be moved towards it (`arm_nudge`): the arm
        follows, or the jaws, closing together, push the held cap and never both touch."""
        nudge = self.ctx.blackboard.arm_nudge
        if nudge is not None:
            self.still.position = self.still.position + nudge * dt
        self.touched = self.touched or bool((readings.pad_force > TOUCH).any())
        timed_out = readings.time - self.pinch_started > PINCH_TIME
        if self.cap.empty and self._lost_where_held():
            self._gone(readings, "closed on nothing")
        elif self.cap.empty:
            self._again(readings, "the fingers closed on nothing")
        elif self.cap.pinched and not self._pressed_outside(readings, dt):
            self._begin_twist(readings)
        elif timed_out and not self.touched and self._lost_where_held():
            self._gone(readings, f"touched nothing with any pad in {PINCH_TIME:.0f} s")
        elif timed_out:
            self._again(readings, f"the pads did not all press the grasp force within {PINCH_TIME:.0f} s")
        if self.phase is not Phase.PINCH:
            return self._toward(readings, self.still, RETURN_SPEED)
        down = self.cap.drop * (self.still.rotation @ self.direction)  # the closing pads' rise (the hand's `_follow`)
        return self._toward(readings, TcpPose(self.still.position + down, self.still.rotation), RETURN_SPEED)

    def _twist(self, readings: Readings, dt: float) -> np.ndarray:
        """Turn about the approach axis through the grasp centre (the lever's feed-forward
        keeps the centre still, unless a motor-only gripper's arm gives way along the jaws'
        line: `_give_way`); on to the pull once turned, back to pinch again early."""
        rotation, position = readings.tcp[:3, :3], readings.tcp[:3, 3]
        torque = abs(float(self.wrench.value[3:] @ self.direction))
        w, left = orientation_twist(self.twisting.goal, rotation)
        if torque > self.torque_limit:
            self._again(readings, f"the twist met {torque:.1f} N m, above UNSCREW_TORQUE_LIMIT")
        elif self.cap.empty:
            self._again(readings, "the fingers closed on nothing while twisting")
        elif readings.time - self.twisting.started > TWIST_TURNS * self.twist_angle / TWIST_SPEED:
            self._again(readings, f"the twist stalled {np.degrees(left):.0f} degrees short")
        elif left < ORIENTATION_TOLERANCE:
            self.wrench.start(readings, settle=False)
            self.pulling = Pulling(position.copy(), rotation.copy())
            self.phase = Phase.PULL
        if self.phase is not Phase.TWIST:
            return np.zeros(6)
        if self._motor_jaws():
            self._give_way(readings, dt)
        w = clamp_norm(w, TWIST_SPEED)
        lever = rotation @ self.grasp_centre
        v = GAIN * (self.twisting.centre - position - lever) + np.cross(w, -lever)
        return np.concatenate([v, w])

    def _pull(self, readings: Readings, dt: float) -> np.ndarray:
        """Back off along the approach: above PULL_FORCE_LIMIT the thread still holds the cap,
        CAP_REMOVED_DISTANCE with the pads on it and the cap is off."""
        pulling = self.pulling
        back = pulling.rotation @ self.direction
        pulled = float((pulling.origin - readings.tcp[:3, 3]) @ back)
        force = abs(float(self.wrench.value[:3] @ self.direction))
        cap = self.cap
        if force > self.pull_force_limit:
            self._again(readings, f"the pull met {force:.1f} N, above PULL_FORCE_LIMIT: the thread still holds")
        elif cap.empty:
            self._again(readings, "the fingers closed on nothing while pulling")
        elif pulled >= self.cap_removed_distance and cap.holding:
            self._hold_here(readings, Phase.OFF)
            self.ctx.blackboard.cap_off = True
            self.finish(Status.DONE, f"cap off after {self.tally.twists} twists, pulled {pulled * 100:.1f} cm with "
                                     f"the pads on it ({self.tally.aligned} alignments, {self.tally.seated} moves "
                                     "off the cap's top)", twists=self.tally.twists)
        elif pulled >= self.cap_removed_distance:
            self._again(readings, "pulled CAP_REMOVED_DISTANCE with no cap between the pads")
        if self.phase is not Phase.PULL:
            return np.zeros(6)
        w, _ = orientation_twist(pulling.rotation, readings.tcp[:3, :3])
        return np.concatenate([-PULL_SPEED * back, w])

    def _release(self, readings: Readings, dt: float) -> np.ndarray:
        """Still while the hand opens; it clears `release` once open."""
        if not self.ctx.blackboard.release:
            self.wrench.start(readings, settle=False)  # the hand open and still: what the return meets is contact
            self.phase = Phase.RETURN
        return self._toward(readings, self.still, RETURN_SPEED)

    def _return(self, readings: Readings, dt: float) -> np.ndarray:
        """Back to the start pose (the twist undone), then pinch again. A gripper's wrist
        pushed along the approach while still over SEAT_SHORT above the start pose is an
        open jaw on the cap's top (the pull drew the jaws up the cap, the untwist swung one
        over it): off the top and round. Lower, the jaws are beside the cap: a jaw the
        untwist drags along its side loads the wrist as much (33-35 N on the Baxter)."""
        start = self.start_pose
        above = float((start.position - readings.tcp[:3, 3]) @ (start.rotation @ self.direction))
        pushed = abs(float(self.wrench.value[:3] @ self.direction))
        if self.room > 0.0 and above > SEAT_SHORT and pushed >= self.threshold:
            self._off_the_top(readings)
            return self._toward(readings, self.still, RETURN_SPEED)
        _, left = orientation_twist(start.rotation, readings.tcp[:3, :3])
        if norm(start.position - readings.tcp[:3, 3]) < ARRIVED and left < ORIENTATION_TOLERANCE:
            self.phase = Phase.PINCH
            self.still = TcpPose(start.position.copy(), start.rotation.copy())
            self.pinch_started, self.yielded, self.touched = readings.time, 0.0, False
            self.tally.pinches += 1
            self.ctx.blackboard.contact = True
        return self._toward(readings, start, RETURN_SPEED)

    def _off(self, readings: Readings, dt: float) -> np.ndarray:
        """The cap is off: hold it where the pull ended."""
        return self._toward(readings, self.still, RETURN_SPEED)

    def _failed(self, readings: Readings, dt: float) -> np.ndarray:
        """Gave up: hold still where it was."""
        return self._toward(readings, self.still, RETURN_SPEED)

    # -- transitions ----------------------------------------------------------------------
    def _jaws_room(self, readings: Readings) -> float:
        """How much wider the open jaws stand than the cap (m; 0 unless a gripper's pads and
        the cap's width are known), and where to look for it (`search`, SEARCH_STEP of that
        room apart) along `jaw_line`, the hand-frame line they close along."""
        if self.cap_width <= 0.0 or len(self.ctx.info.hand.pads) != 2:
            return 0.0
        gap = self._jaws_gap(readings)
        room = gap - self.cap_width
        self.search = search_offsets(SEARCH_STEP * room, SEARCH_POINTS)
        return max(room, 0.0)

    def _jaws_gap(self, readings: Readings) -> float:
        """How far apart the two jaws' pads stand (their joint's reading); sets `jaw_line`."""
        left, right = self.ctx.info.hand.pad_surfaces(readings.hand_q)[:2, :3, 3]
        gap = norm(left - right)
        self.jaw_line = (left - right) / gap
        return gap

    def _pressed_outside(self, readings: Readings, dt: float) -> bool:
        """Jaws without tactile pads (one force for both, their motor's) that say they grip
        the cap while standing wider apart than it, the wrist pushed along their line: one
        jaw presses the cap from outside, the arm holding it there, the other clear of it,
        and the motor reads the grasp force all the same (the Baxter, docs/unscrew-campaign.md;
        tactile pads say so themselves). The arm yields the way the wrist is pushed, no
        further than the jaws' room, until both close on the cap."""
        if not self._motor_jaws() or self._jaws_gap(readings) <= self.cap_width:
            return False
        step = self._yield_step(readings, dt)
        if step == 0.0:
            return False
        if self.yielded < self.room:
            self.yielded += abs(step)
            self.still.position = self.still.position + step * (self.still.rotation @ self.jaw_line)
        return True

    def _give_way(self, readings: Readings, dt: float) -> None:
        """A twist about the grasp centre while the cap's axis stands off it across the jaws'
        width (which a motor's one force cannot place) swings the cap's centre along the
        jaws' line: one jaw drives into the cap, forcing the other off it and the jaws open
        to their stop (the Baxter, docs/unscrew-campaign.md). The arm yields the way the
        wrist is pushed along their line, as the pinch's yield does, so that the hand turns
        about the cap's own axis; no further than the alignment moves it (MAX_ALIGN)."""
        twisting = self.twisting
        step = self._yield_step(readings, dt)
        if step == 0.0 or abs(twisting.yielded + step) > MAX_ALIGN:
            return
        twisting.yielded += step
        twisting.centre = twisting.centre + step * (readings.tcp[:3, :3] @ self.jaw_line)

    def _motor_jaws(self) -> bool:
        """Jaws without tactile pads around a cap of known width: their one force, the motor's,
        says nothing of which jaw presses the cap; the wrist does."""
        return self.room > 0.0 and self.ctx.info.hand.pads[0].taxels is None

    def _lost_where_held(self) -> bool:
        """Does a pinch here that finds nothing say the cap left the pads? Only where they
        pinched and twisted it (`held`) round its side, where a cap on its thread stays between
        them: not jaws that know only their motor (`_gone`), nor jaws pinching from above their
        depth (`_above_depth`), whose pads' tips pinch the cap's rim and slide across its top to
        close on nothing beyond, the cap on its thread (the Melfa without the alignment,
        PyBullet, docs/unscrew-campaign.md)."""
        return self.held and not self._motor_jaws() and not self._above_depth()

    def _above_depth(self) -> bool:
        """A gripper's jaws pinch from over SEAT_SHORT above where the descent was sending them
        (`short`): it stopped on a jaw on the cap's top, and no seat has brought them down."""
        return self.room > 0.0 and self.short > SEAT_SHORT

    def _yield_step(self, readings: Readings, dt: float) -> float:
        """How far (m, signed along `jaw_line`) the arm yields this tick to the wrist's push
        along the jaws' line, one jaw pressing the cap harder: at OUTSIDE_SPEED the way it
        is pushed, once the push is past STALL_CONTACT of the threshold; else 0."""
        push = float(held_wrench(self.ctx.info.hand, readings)[:3] @ self.jaw_line)
        if abs(push) < STALL_CONTACT * self.threshold:
            return 0.0
        return float(np.sign(push)) * OUTSIDE_SPEED * dt

    def _begin_seat(self, readings: Readings, seating: Seating) -> None:
        self.wrench.start(readings)  # in free air, over the cap
        self.seating = seating
        seating.stall.reset(readings.time)
        self.still = TcpPose(readings.tcp[:3, 3].copy(), self.start_pose.rotation)
        self.phase = Phase.SEAT

    def _jaw_on_top(self, readings: Readings) -> None:
        """The wrist felt the jaws meet something short of their depth: a jaw on the cap's top.
        Off the top and across to the next point of the jaw grasp's search along the jaws'
        line (`search_offsets`, around where the descent was first going, to either side in
        turn: the wrist's torque does not say which jaw stands on the cap, docs/unscrew-campaign.md),
        steps narrower than the window in which the jaws clear the cap. Up to SEAT_RISE over
        the cap's top as the first stop felt it (`start_pose`), or over here if higher: a jaw
        stopped lower, down the cap's side, is still beside the cap that far up. With the
        search spent: pinch here."""
        if self.tally.seated >= len(self.search):
            self._pinch_from(readings)
            return
        seating = self.seating
        rotation = self.start_pose.rotation
        goal = seating.first + rotation @ (self.search[self.tally.seated] * self.jaw_line)
        along, here = rotation @ self.direction, readings.tcp[:3, 3]
        up = here + (min(0.0, float((self.start_pose.position - here) @ along)) - SEAT_RISE) * along
        seating.route, seating.goal, seating.watched = [up, up + goal - seating.goal], goal, False
        self.tally.seated += 1
        self._hold_here(readings, Phase.ACROSS)

    def _off_the_top(self, readings: Readings) -> None:
        """The return met the cap's top: up SEAT_RISE off it, across to over the start pose
        (the twist undone there, clear of the cap), and down to it as the seat goes down,
        watched, the jaw grasp's search about it if a jaw meets the cap again; that pinch
        is the next one."""
        start = self.start_pose
        along = start.rotation @ self.direction
        up = readings.tcp[:3, 3] - SEAT_RISE * along
        over = start.position + float((up - start.position) @ along) * along
        self.seating = Seating(start.position.copy(), start.position.copy(), [up, over])
        self.tally.pinches += 1
        self._hold_here(readings, Phase.ACROSS)

    def _gone(self, readings: Readings, felt: str) -> None:
        """The fingers closed on nothing where they had pinched and twisted the cap, or closed
        with no pad touching anything (a Barrett's fingers stopped by their bare links, over
        FINGER_MIN_DISTANCE apart, docs/unscrew-campaign.md): a cap on its thread stays where
        it was pinched, so this one came free and left the pads (a pinch across its axis
        squeezes a freed cap out). Give up now, saying so (`felt`: what this pinch did): the
        remaining pinches would find nothing too. Not where the jaws know only their motor
        (`_motor_jaws`): their one force cannot place a cap pinched off their line, and the
        Baxter's paddles, 13 mm across a cap's axis, held a chord of it, gave way in the twist
        and slid off the cap, still on its thread, in the next pinch; nor from above their
        depth (`_lost_where_held`)."""
        self._hold_here(readings, Phase.FAILED)
        self.finish(Status.ERROR, f"the cap came off its thread and left the pads after {self.tally.twists} twists: "
                                  f"pinch {self.tally.pinches} {felt} where they had held it "
                                  f"({self.tally.ended})", twists=self.tally.twists)

    def _pinch_from(self, readings: Readings) -> None:
        """Pinch here: every later pinch starts from this pose."""
        self.held = False
        position = readings.tcp[:3, 3].copy()
        self.start_pose = TcpPose(position, self.start_pose.rotation)
        self.short = float((self.depth - position) @ (self.start_pose.rotation @ self.direction))  # m over the depth
        self.still = TcpPose(position.copy(), self.start_pose.rotation)
        self.pinch_started, self.yielded, self.touched = readings.time, 0.0, False  # touched: a pad felt something
        self.phase = Phase.PINCH
        self.ctx.blackboard.contact = True  # the hand is over the cap: it may close

    def _begin_twist(self, readings: Readings) -> None:
        """Turn the other way from a tightening turn about the approach axis: a right-hand
        thread opens counter-clockwise seen from the hand; no further than the wrist joint
        that rolls the hand can turn from where it is (each return turns it back)."""
        rotation, position = readings.tcp[:3, :3], readings.tcp[:3, 3]
        angle = min(self.twist_angle, self._wrist_room(readings) - WRIST_MARGIN)
        if angle < MIN_TWIST:
            self._hold_here(readings, Phase.FAILED)
            self.finish(Status.ERROR, f"the wrist joint '{self.ctx.info.arm_joints[-1]}' has "
                                      f"{np.degrees(angle + WRIST_MARGIN):.0f} degrees left to turn the cap open: "
                                      "turn the hand the other way about its approach before the unscrew",
                        twists=self.tally.twists)
            return
        self.tally.twists += 1
        self.held = True
        self.wrench.start(readings, settle=False)  # the squeeze's own load is no torque of the thread's
        goal = axis_rotation(rotation @ self.direction, -angle) @ rotation
        self.twisting = Twisting(goal, position + rotation @ self.grasp_centre, readings.time)
        self.phase = Phase.TWIST

    def _wrist_room(self, readings: Readings) -> float:
        """How far (rad) the last arm joint can turn the way an opening twist turns it
        (`wrist_turn`: its turn per turn of the hand about the approach); unlimited where
        the factory names no such joint."""
        info = self.ctx.info
        if self.wrist_turn > 0.0:
            return float(readings.arm_q[-1] - info.arm_lower[-1])
        if self.wrist_turn < 0.0:
            return float(info.arm_upper[-1] - readings.arm_q[-1])
        return np.inf

    def _again(self, readings: Readings, why: str) -> None:
        """A twist or pull ended early, or a pinch found nothing: align on the cap, open the
        hand, go back and pinch again; or, the pinches spent, give up saying why."""
        self.tally.ended = why
        if self.tally.pinches >= self.max_pinches:
            # motor jaws twisted, then shut on nothing: whether the cap came off, unknown (`_gone`
            # tells it where the pads feel the cap)
            lost = self.cap.empty and self.tally.twists > 0 and self._motor_jaws()
            where = "no cap between the pads, on its thread or off," if lost else "the cap not felt to come off"
            above = f" (the jaws {self.short * 1000:.0f} mm over their depth round the cap: a jaw on its top)"
            self._hold_here(readings, Phase.FAILED)
            self.finish(Status.ERROR, f"{where} after {self.tally.pinches} pinches and {self.tally.twists} "
                                      f"twists: {why}{above if self._above_depth() else ''}", twists=self.tally.twists)
            return
        self._align()
        self._hold_here(readings, Phase.RELEASE)
        self.ctx.blackboard.release = True
        self.ctx.blackboard.contact = False

    def _align(self) -> None:
        """The reactive alignment (Fig. 3.12): move the start pose across the approach so that
        the grasp centre lies on the cap's axis, as the pads' contacts averaged over the
        pinch and the twist place it; no further than MAX_ALIGN at once."""
        axis = self.cap.axis
        if not self.alignment or axis is None:
            return
        start = self.start_pose
        along = start.rotation @ self.direction
        off = axis - start.position - start.rotation @ self.grasp_centre
        off = off - float(off @ along) * along
        if norm(off) >= (MOTOR_ALIGN_TOLERANCE if self._motor_jaws() else ALIGN_TOLERANCE):
            start.position = start.position + clamp_norm(off, MAX_ALIGN)
            self.tally.aligned += 1

    def _hold_here(self, readings: Readings, phase: Phase) -> None:
        self.still = TcpPose(readings.tcp[:3, 3].copy(), readings.tcp[:3, :3].copy())
        self.phase = phase

    def _toward(self, readings: Readings, pose: TcpPose, speed: float) -> np.ndarray:
        """The twist (world frame) that takes the TCP to `pose` at no more than `speed`."""
        w, _ = orientation_twist(pose.rotation, readings.tcp[:3, :3])
        return np.concatenate([clamp_norm(GAIN * (pose.position - readings.tcp[:3, 3]), speed), w])

