"""The arm side of the robust parallel-jaw grasp (thesis 3.3.1; D5 chapter 3): it corrects
an approach that left the jaws off the object before the hand closes.

The approach may end tilted, with a jaw resting on the object's top, above the object,
or beside it, pressing its side. So the arm first rises above the object's top (as the
task believes it), then descends along the world's vertical on the wrist sensor, at most
down to the object's centre (where the TCP grasps it). Where the first contact sits
across the hand says what was met: under one jaw, above the object's top (that jaw is on
the top: move the hand across by that much, along the jaws' width no further than the
jaw is wide, and no further than halfway back to where an earlier contact said the other
side, so that moves across bracket the object instead of swinging over it; rise, descend again),
or under the middle or below the top (the support under both jaws, or the palm on the
object: the jaws straddle its place, so close). The descent stops with the fingertips
clear of the support. The jaws closing on nothing (`jaws_empty`) means the object lies
beyond the jaws' width, where closing does not sweep: the arm rises and goes where the
palm's contact placed the object, or a step beyond the pads' edge that brushed it on the
way (`jaws_brushed`) or beyond where the wrist felt a finger's bare rim push it (`RimLever`),
or else to the next point of a bounded search along the jaws' width, alternating sides, around where the approach left it and the moves
across have since taken it. While the jaws close it follows the hand's `arm_nudge`
(re-centring on the pads' contact) and ends once `fingers_stopped`. Jaws that reopen from a
grip pressed partly through a finger's bare rim (`jaws_rim`) have the object between them,
beyond the pads' edge: the arm moves along their width, towards where the weaker pad felt the
object or else the rim's lever, by a pad's half width, and the jaws close again there. A task that knows no
object may give it the top a perceive state saw (`object_top`): it stands in for the object's
top, and the jaws do not close before the fingertips are past it; a jaw met there moves the
jaws halfway to it (the top spans from the hand's axis to that jaw), and the first such contact
that no move across is left for turns the jaws a quarter turn about the vertical, and the hand
comes down again. A hand pressed far beyond any grasp's need (`WEDGED`: between a wall and the
pile) does not close there: it eases off the way the press pushes it, rises, and the grasp
fails, saying so. Asked to (`locate_along`: its place cannot weigh where the jaws hold the
object), a hand with a range sensor along its approach axis sweeps the open jaws along their
width before its first close of a descent, sees where the object's top spans
(`primitives.arm.jaw_span`) and closes on its middle; it tells the place whether it did
(`LOCATED_ALONG`). Jaws without tactile images descend slowly past a ball's upper half, and
place it from a contact by the sphere's geometry (`primitives.arm.jaw_ball`). Over a known
container, with the open fingertips over its rim and over the top the task believes in, nothing
can be met: the grasp does not rise first, and its descent goes at a free move's speed down to
just over them.
"""

from __future__ import annotations

from collections import deque
from enum import Enum

import numpy as np

from primitives.arm.approach_phases import APPROACH_ACCELERATION
from primitives.arm.motion import (
    GAIN,
    ORIENTATION_TOLERANCE,
    SUPPORT_BAND,
    Stall,
    TwistShaper,
    about_vertical,
    clamp_norm,
    norm,
    orientation_twist,
    roll_room,
    unit,
    what_stops,
)
from primitives.arm.jaw_ball import ROLLING_DESCENT, BallUnderJaws
from primitives.arm.jaw_rim import RimLever
from primitives.arm.jaw_span import BeamSpan, Sweep
from primitives.arm.move import arm_output
from primitives.arm.walls import FREE_SPEED, RIM_CLEARANCE, KnownWalls
from primitives.base import Context, ControlData, Controller, Status
from primitives.blackboard import ARM_TWIST, EMPTY_HAND, LOCATED_ALONG
from primitives.filters import ContactWrench, contact_across, world_load
from primitives.robot import Readings
from primitives.search import search_offsets

ARRIVED = 0.002  # m: a waypoint of the correction counts as reached
# m: the rise before a move across counts as made this near its top, and the arm goes on
# across without slowing into it (0.2 s of each 2.3 s move between search points, in free air)
PASSED = 0.005
UP = np.array([0.0, 0.0, 1.0])
FLAT = np.array([1.0, 1.0, 0.0])
# rad: a hand turned less than this from pointing down corrects along the vertical, one turned
# further (a grasp from the side) along its own approach axis (the robust grasp levels a hand
# within its `level_within`, 30 degrees by default, and the factory checks reach alike)
FROM_ABOVE = np.radians(30.0)
STALL_TIME = 0.5  # s without descending 1 mm while pressing: the descent is on a contact
STALL_CONTACT = 0.5  # of force_threshold: pressing that much when stalled is a contact
FLOOR_CLEARANCE = 0.005  # m: the descent stops with the fingertips this far above the support
PRESSED = 5.0  # N up on the wrist, beyond the empty hand's load, while the jaws close: pressed on the support
RELIEF_GAIN = 0.002  # m/s per newton pressed beyond PRESSED: the arm rises to take it off
MAX_RELIEF = 0.02  # m the arm rises for that in one close, at most
FREE_LOAD_WINDOW = 0.1  # s: the empty hand's load is the wrist's mean over the end of a move in free air
# m the fingertips reach past a seen top before the jaws close: a seen top is good to a few mm (docs/empty-the-box.md)
PAST_SEEN_TOP = 0.005
# m over a seen top beyond which the fingertips met something else: a descent's start from over the rim read as a
# contact 7.5 cm over a standing speaker's top, and a turn there was spent on it (docs/empty-the-box.md)
OVER_SEEN_TOP = 0.02
# N on the wrist beyond the empty hand's load: no grasp needs a tenth of it (a contact 2 N, a grip 15 N, a
# close on the table 96 N before its relief); a hand pressed so hard is wedged (docs/empty-the-box.md)
WEDGED = 150.0
WEDGE_TIME = 0.1  # s the press lasts: a knock is over sooner (PyBullet's wrist read 158 N in a tick on a top)
WEDGE_BACK_OFF = 0.01  # m a wedged hand moves the way the press pushes it, and so eases it, before it rises
SPAN_SPEED = 0.1  # m/s the open jaws move along their width while the range sensor looks (its edges to 0.5 mm a tick)
# rad the jaws turn about the vertical, once, where a jaw met the seen top: a top longer across the jaws than they
# open (a speaker lying 7.2 cm across them), or one no move across reaches (a roll of tape by a wall), fits
# the other way (docs/empty-the-box.md); a look costs 15-48 s, the turn and a descent a few
TURN = np.pi / 2


class JawPhase(Enum):
    """Where the jaw grasp's arm is; each tick runs the one it is in."""

    MOVE = "move"  # rising clear of a contact, then across to where to look next
    DESCEND = "descend"  # down on the wrist sensor until a contact or the grasp height
    SPAN = "span"  # open, along the jaws' width while the range sensor finds the top's edges, then over its middle
    CLOSE = "close"  # holding still (following the re-centring) while the jaws close
    ALONG = "along"  # the jaws reopened off a finger's bare rim: along their width, then close again
    HOLD = "hold"  # the jaws hold the object, or the grasp has ended in an error


class Bracket:
    """Moves across the jaws (hand y) that close in on the object: a contact under one jaw says
    the object lies beyond it on that side, so a move goes no further than halfway to the
    nearest place where a contact said the other side (halved against the last move only, a
    third move swung the Melfa's jaws back past the first contact's place: docs/robust-grasp.md)."""

    def __init__(self) -> None:
        self.at = 0.0  # m: the hand's y since the first contact, the sum of the moves across
        self.low = -np.inf  # the furthest -y place where a contact said +y
        self.high = np.inf  # the furthest +y place where a contact said -y

    def move(self, across: float) -> float:
        """The move for a contact at `across` (hand y) from here; the hand makes it."""
        if across > 0.0:
            self.low = max(self.low, self.at)
            room = self.high - self.at
        else:
            self.high = min(self.high, self.at)
            room = self.at - self.low
        across = float(np.sign(across)) * min(abs(across), room / 2.0)
        self.at += across
        return across


class JawGraspCorrection(Controller):
    """The corrections above, one phase at a time: move (rise, across), descend, close, hold."""

    def __init__(self, ctx: Context) -> None:
        super().__init__(ctx)
        p = self.params
        self.threshold = float(p["force_threshold"])
        self.clearance = float(p["clearance"])
        self.above = float(p["above_object"])
        self.wrist_to_tcp = float(p["wrist_to_tcp"])
        self.reach = float(p["fingertip_reach"])
        self.tip_extent = np.asarray(p["fingertip_extent"], float)  # m, the open fingertips' (x, y) reach sideways
        self.back_off = float(p["back_off"])
        self.speed = float(p["correction_velocity"])
        self.descent = float(p["descent_velocity"])
        self.wrist_roll = float(p["wrist_roll"])
        self.max_depth = float(p["max_depth"])
        self.centre_band = float(p["centre_band"])
        self.max_shift = float(p["max_shift"])
        self.max_shifts = int(p["max_shifts"])
        self.jaw_half_width = float(p["jaw_half_width"])
        # m: a move along the jaws this long takes a contact on a finger's rim beside a pad onto the pad
        self.pad_half_width = max((pad.half_size[0] for pad in ctx.info.hand.pads), default=0.0)
        self.pad_half_height = max((pad.half_size[1] for pad in ctx.info.hand.pads), default=0.0)
        self.step = float(p["search_step"])
        self.offsets = search_offsets(self.step, int(p["search_points"]))
        self.locate = bool(p["locate_along"])
        top = p.get("object_top")
        self.seen_top = None if top is None else float(top)  # m, world z: the top a perceive state saw
        self.walls = KnownWalls.of(ctx)
        self.contact = ContactWrench(float(p["filter_time"]))
        self.move_stall = Stall()  # a correction's waypoint the arm cannot get to
        self.descent_stall = Stall(STALL_TIME)  # a descent on a contact
        # where a close pushed the object when its pads did not feel it; near the axis as the centre band, no side
        self.rim = RimLever(self.threshold, self.centre_band)
        self.shaper = TwistShaper()  # a sudden reversal shakes the wrist like a contact
        # One sample of the Baxter's virtual wrist sensor is off by 0.2 N or more: a 20 g object.
        self.free_loads: deque[np.ndarray] = deque(maxlen=max(1, round(FREE_LOAD_WINDOW / ctx.info.control_period)))

    def start(self, readings: Readings) -> None:
        # The hand keeps the tilt the approach left: turning it upright drove the Melfa's
        # wrist (j4) onto its limit in 4 of 20 trials with the seeds' approach error.
        self.rotation = readings.tcp[:3, :3].copy()
        hand_z = readings.tcp[:3, 2]
        self.vertical = float(-hand_z[2]) >= np.cos(FROM_ABOVE)
        # m the open fingertips' lowest corner lies below the TCP, the hand turned as it is kept
        # (a tilted hand's corner, not its middle, meets the table: docs/robust-grasp.md)
        down = self.rotation[2]
        self.tip_depth = float(-down[2] * self.reach + np.abs(down[:2]) @ self.tip_extent)
        # the way the hand backs off: up, or back along the approach of a grasp from the side
        self.back = UP if self.vertical else -hand_z / norm(hand_z)
        # the search's way: the hand's x, or level across a grasp from the side (its x would
        # search up and down the object, and down into the table)
        self.search_way = None if self.vertical else unit(np.cross(self.back, UP))
        self.ball = BallUnderJaws.of(self.ctx, float(self.tip_extent[1]), self.vertical)
        self.centre = readings.tcp[:3, 3].copy()  # where the approach believes the object is
        self.shaper.start(self.ctx.memory.get(ARM_TWIST))
        self.searched = 0
        self.shifts = 0
        self.alongs = 0  # moves along the jaws off a finger's rim
        self.turned = False  # the jaws have been turned a quarter turn off a seen top: they are, once
        self.bracket = Bracket()  # the moves across so far, and where their contacts placed the object
        self.hint: np.ndarray | None = None  # where the last contact says the object is, world frame
        self.hinted = False  # a contact's hint has been followed: one is, once
        self.brushed = False  # a hint from the pads' brushing the object, or a rim's push, has been taken: one is, once
        self.wedged: str | None = None  # why the grasp fails once the wedged hand has backed off and risen
        self.pressed_since: float | None = None  # when the press past WEDGED began
        self.tared = False  # this grasp has read its empty hand (EMPTY_HAND): the approach may have left it pressing
        self.ctx.blackboard.contact = False
        self.spannable = False  # the next close first finds the object's middle along the jaws
        self.sweep: Sweep | None = None  # that sweep, once begun
        # an approach that ended in free air over a known container's rim touches nothing to rise off
        clear = self._over_rim(readings.tcp[:3, 3]) > 0.0
        self._rise(readings, np.zeros(3), self._above_object(), 0.0 if clear else self.clearance)

    def _depth(self, point: np.ndarray) -> float:
        """How far back `point` lies: its height, or along `back` for a grasp from the side."""
        return float(point[2]) if self.vertical else float(point @ self.back)

    def _off_line(self, v: np.ndarray) -> np.ndarray:
        """`v` without its part along `back`."""
        return v * FLAT if self.vertical else v - float(v @ self.back) * self.back

    def _level(self, v: np.ndarray) -> np.ndarray:
        """A move across the hand's way in: level too for a grasp from the side, which
        closes at the height the task put it at."""
        return self._off_line(v) * (1.0 if self.vertical else FLAT)

    def _at_depth(self, point: np.ndarray, depth: float) -> np.ndarray:
        """`point` moved along `back` to `depth`."""
        if self.vertical:
            return np.array([point[0], point[1], depth])
        return point + (depth - float(point @ self.back)) * self.back

    def _searching(self, readings: Readings) -> np.ndarray:
        """The way the search looks for the object (world frame)."""
        return readings.tcp[:3, 0] if self.search_way is None else self.search_way

    def _object_top(self) -> float:
        """The depth of the object's face the hand meets first, as the task believes it: its
        top, or its side facing a grasp from the side; for a task that knows no object, the
        top a perceive state saw (`object_top`) from above (-inf: neither says)."""
        obj = self.ctx.object
        if obj is None or obj.pose is None:
            return self.seen_top if self.seen_top is not None and self.vertical else -np.inf
        centre = np.asarray(obj.pose.position, float)
        return self._depth(centre) + (obj.half_height if self.vertical else obj.footprint_width / 2.0)

    def _grasp_height(self) -> float:
        """The depth where the TCP closes on the object: level with its centre, as the task
        believes it (or halfway down to the support from the top a perceive state saw: the
        middle of an object standing there), or higher for an object shorter than the jaws'
        pads, whose fingertips would otherwise press on the support (and its pads feel that
        as a grip); on its axis for a grasp from the side."""
        obj = self.ctx.object
        if obj is not None and obj.pose is not None:
            centre = self._depth(np.asarray(obj.pose.position, float))
        elif self.seen_top is not None and self.vertical:
            centre = (self.seen_top + self._support()) / 2.0
        else:
            centre = -np.inf
        return max(centre, self._support() + self.tip_depth + FLOOR_CLEARANCE) if self.vertical else centre

    def _support(self) -> float:
        """Height of the support under the hand: the floor of a known container it is over
        (a box's floor stands its wall's thickness over the table), else the table's z = 0."""
        return self.walls.support(self.line)

    def _above_object(self) -> float:
        """TCP depth from which a descent meets the object's top (or facing side) first."""
        return self._object_top() + self.above

    def _over_rim(self, position: np.ndarray) -> float:
        """How far (m) the open fingertips of a hand from above at `position` (its TCP, world)
        are over the line down to which nothing can be met: RIM_CLEARANCE over the rim of the
        known container they are over, and over the top the task believes in (the library's
        objects lying in a box reach no higher than its rim); -inf over no known container, or
        for a grasp from the side."""
        rim = self.walls.rim(position)
        if rim is None or not self.vertical:
            return -np.inf
        return float(position[2]) - self.tip_depth - max(rim, self._object_top()) - RIM_CLEARANCE

    def _rise(self, readings: Readings, across: np.ndarray, height: float = -np.inf,
              clearance: float | None = None) -> None:
        """Back `clearance` (by default the grasp's) clear of the contact, at least to depth `height`,
        then `across` (world frame), then descend again."""
        here = readings.tcp[:3, 3]
        rise = self.clearance if clearance is None else clearance
        up = self._at_depth(here, max(self._depth(here) + rise, height))
        # from inside a box, a search point beyond its wall is a move into the wall (it pressed
        # the hand there at 240 N; Melfa, MuJoCo, docs/empty-the-box.md): kept inside it
        self.route = [up, self.walls.inside(self.rotation, up + self._level(across), here)]
        self.phase = JawPhase.MOVE
        self.towards: np.ndarray | None = None  # the waypoint `move_stall` is measured to
        self.free_loads.clear()

    def update(self, readings: Readings, dt: float) -> ControlData:
        board = self.ctx.blackboard
        position = readings.tcp[:3, 3]
        w, angle = orientation_twist(self.rotation, readings.tcp[:3, :3])
        v = np.zeros(3)
        if self.phase is not JawPhase.HOLD and self.tared and self.wedged is None:
            self._check_wedged(readings)
        if self.phase is JawPhase.MOVE:
            self.free_loads.append(world_load(readings))
            v = self._follow(readings, angle)
        elif self.phase is JawPhase.DESCEND:
            v = self._descend(readings, dt)
        elif self.phase is JawPhase.CLOSE:
            v = self._close(readings, dt)
        elif self.phase is JawPhase.ALONG:
            v = self._along(readings)
        elif self.phase is JawPhase.SPAN:
            v = self._span(readings, dt)
        relieved = True
        if self.phase is JawPhase.CLOSE:
            relieved = self._relieve(readings, dt)
        board.pressing = not relieved
        if self.phase in (JawPhase.CLOSE, JawPhase.HOLD):
            v = GAIN * (self.goal - position) + (v if self.phase is JawPhase.CLOSE else 0.0)
        if self.phase is JawPhase.CLOSE and board.fingers_stopped and relieved:
            self.phase = JawPhase.HOLD
            along = f", {self.alongs} along the jaws off a rim" if self.alongs else ""
            along += ", turned a quarter turn off the seen top" if self.turned else ""
            self.finish(Status.DONE, f"the jaws hold the object after {self.shifts} moves across{along} and "
                                     f"{self.searched + self.hinted} search points")
        return arm_output(self.shaper(np.concatenate([v, w]), dt))

    def _follow(self, readings: Readings, angle: float) -> np.ndarray:
        position = readings.tcp[:3, 3]
        goal = self.route[0]
        if len(self.route) > 1 and norm(goal - position) < PASSED:
            self.route.pop(0)
            goal = self.route[0]
        if norm(goal - position) < ARRIVED and angle < ORIENTATION_TOLERANCE:
            self.route.pop(0)
            if not self.route:
                if self.wedged is not None:
                    self.phase, self.goal = JawPhase.HOLD, position.copy()
                    self.finish(Status.ERROR, self.wedged)
                    return np.zeros(3)
                if self.ctx.blackboard.jaws_empty or len(self.free_loads) < self.free_loads.maxlen:
                    self.route = [goal]  # the jaws are still opening, or the empty hand not yet weighed
                    return np.zeros(3)
                self._start_descent(readings)
                return np.zeros(3)
            goal = self.route[0]
        if goal is not self.towards:
            self.towards = goal
            self.move_stall.reset(readings.time)
        if self.move_stall.stalled(norm(goal - position), readings.time):
            info = self.ctx.info
            self.phase, self.goal = JawPhase.HOLD, position.copy()
            self.finish(Status.ERROR, f"the correction made no progress for {self.move_stall.patience:g} s, "
                                      f"{norm(goal - position) * 100:.1f} cm from its waypoint: "
                                      f"{what_stops(readings.arm_q, info.arm_joints, info.arm_lower, info.arm_upper)}")
            return np.zeros(3)
        return clamp_norm(GAIN * (goal - position), self.speed)

    def _check_wedged(self, readings: Readings) -> None:
        """A hand pressed WEDGED beyond the empty hand's load (between a wall and the pile) for
        WEDGE_TIME does not close there: it moves the way the press pushes it, which eases it,
        rises clear, and the grasp fails, saying so."""
        press = world_load(readings) - self.ctx.memory[EMPTY_HAND]
        if norm(press) < WEDGED:
            self.pressed_since = None
            return
        if self.pressed_since is None:
            self.pressed_since = readings.time
        if readings.time - self.pressed_since < WEDGE_TIME:
            return
        here = readings.tcp[:3, 3]
        eased = self.walls.inside(self.rotation, here + WEDGE_BACK_OFF * unit(press), here)
        self.route = [eased, self._at_depth(eased, self._depth(eased) + self.clearance)]
        self.phase, self.towards = JawPhase.MOVE, None
        self.ctx.blackboard.contact = False
        self.wedged = f"the wrist pressed {norm(press):.0f} N: wedged, it backed off and rose rather than close there"

    def _start_descent(self, readings: Readings) -> None:
        self.contact.start(readings)
        # Risen clear of every contact, the hand weighs only itself. The grasp's start is no
        # such moment: the approach's guarded descent may have just stopped on the object's
        # top, and a tare pressed 4.3 N up read a lifted cylinder as no load at all.
        free = self.free_loads or [world_load(readings)]
        self.ctx.memory[EMPTY_HAND] = np.mean(np.array(free), axis=0)
        self.tared = True
        self.phase = JawPhase.DESCEND
        self.top = self._depth(readings.tcp[:3, 3])
        self.line = readings.tcp[:3, 3].copy()  # the descent keeps to the vertical through here
        self.descent_stall.reset(readings.time, self.top)
        self.falling = self.descent  # m/s the descent goes at (`_descent_speed`)
        obj = self.ctx.object
        self.spannable = self.locate and self.ctx.info.has_range and self.vertical and obj is not None \
            and obj.pose is not None
        if self.spannable:
            self.ctx.memory[LOCATED_ALONG] = False

    def _descend(self, readings: Readings, dt: float) -> np.ndarray:
        wrench = self.contact.update(readings, dt)
        z = self._depth(readings.tcp[:3, 3])
        stalled = self.descent_stall.stalled(z, readings.time) and self.contact.force >= STALL_CONTACT * self.threshold
        # From the side the jaws straddle the object's place on their way in, and a push
        # tips a standing object long before the wrist feels it (0.4 N tips a 0.2 kg bottle
        # 4 cm wide pushed 9 cm up; the Melfa's contact is 2 N): only a blocked descent has met it
        if (self.contact.force >= self.threshold and self.vertical) or stalled:
            self._met(readings, wrench)
        elif self.top - z >= self.max_depth or z <= self._grasp_height():
            self._close_here(readings, 0.0)
        if self.phase is not JawPhase.DESCEND:
            return np.zeros(3)
        # Held on its vertical: the arm makes a twist only roughly where damped least squares
        # trades accuracy for bounded joint speeds (near a wrist singularity the Melfa's jaws
        # drifted 8 mm sideways in an 8 cm descent, off the object they had found).
        drift = self._off_line(self.line - readings.tcp[:3, 3])
        return GAIN * drift - self._descent_speed(readings, dt) * self.back

    def _descent_speed(self, readings: Readings, dt: float) -> float:
        """`descent_velocity`, or faster, up to FREE_SPEED, while the open fingertips are over the
        line where nothing can be met (`_over_rim`): speeding up and slowing down at
        APPROACH_ACCELERATION (a sudden start reads on the wrist as a contact), so that they
        reach it at `descent_velocity`; slower (ROLLING_DESCENT) while they pass the upper half
        of a ball that jaws without tactile images would kick away (`BallUnderJaws`)."""
        over = self._over_rim(readings.tcp[:3, 3])
        if over <= 0.0:
            self.falling = self.descent
            if self.ball is not None and self.ball.passing(float(readings.tcp[2, 3]) - self.tip_depth):
                return ROLLING_DESCENT * self.descent
            return self.descent
        braking = float(np.sqrt(self.descent**2 + 2.0 * APPROACH_ACCELERATION * over))
        self.falling = min(FREE_SPEED, braking, self.falling + APPROACH_ACCELERATION * dt)
        return self.falling

    def _met(self, readings: Readings, wrench: np.ndarray) -> None:
        """The first contact of a descent: where it sits across the hand says what it is."""
        across = self._contact_across(readings, wrench)
        off_centre = across is not None and norm(across) > self.centre_band and self.vertical
        below_top = self._depth(readings.tcp[:3, 3]) < self._object_top()
        if below_top or not off_centre or self.shifts >= self.max_shifts:
            # Below the object's top the jaws straddle its place: close, and should they
            # close on nothing, look first where the contact was (the palm on its top, as
            # wide as the hand; not the fingertips on the support, which say nothing of
            # the object). Only once: a contact that sent the jaws to close on nothing was
            # no object's top, and following each next one walks the hand away (docs/constants.md).
            on_support = self.vertical and float(readings.tcp[2, 3]) - self.tip_depth - self._support() < SUPPORT_BAND
            self.hint = None if not off_centre or on_support or self.hinted else \
                readings.tcp[:3, 3] + readings.tcp[:3, :3] @ clamp_norm(across, self.max_shift)
            if self._at_seen_top(readings):
                # The fingertips barely past the top a perceive state saw: the pads would close
                # over it. The jaws turn and come down again, once; then the hand goes on as if
                # they had closed there on nothing.
                self.goal = readings.tcp[:3, 3].copy()
                if not self.turned and self._on_seen_top(readings):
                    self._turn(readings)
                    return
                self._search_on(readings, "a jaw met something with the fingertips at the seen top")
                return
            self._close_here(readings, self.back_off, touching=True)
            return
        shift = readings.tcp[:3, :3] @ self._jaw_move(readings, across)
        self.shifts += 1
        self.centre = self.centre + self._level(shift)  # the search goes on from there
        self._rise(readings, shift)

    def _jaw_move(self, readings: Readings, across: np.ndarray) -> np.ndarray:
        """The move across (hand frame) for a jaw on the object's top at `across`: the torque's
        lever along the jaws' width is short and noisy, and the contact lies within the jaw's
        width anyway; across the jaws, bracketed by the contacts before, halfway on a seen top."""
        x = float(np.clip(across[0], -self.jaw_half_width, self.jaw_half_width))
        y = float(np.clip(across[1], -self.max_shift, self.max_shift))
        # A jaw on the top a perceive state saw where the hand came down: the top spans from the
        # hand's axis to the jaw, and the jaws go over its middle (all the way, the other jaw came
        # down on the top where the hand's axis had been: docs/empty-the-box.md)
        return np.array([x, self.bracket.move(y / 2.0 if self._on_seen_top(readings) else y), 0.0])

    def _at_seen_top(self, readings: Readings) -> bool:
        """Whether the fingertips of a hand from above are not yet PAST_SEEN_TOP past the top a
        perceive state saw: a jaw meeting something there has met that top."""
        return self.seen_top is not None and self.vertical and \
            float(readings.tcp[2, 3]) - self.reach > self.seen_top - PAST_SEEN_TOP

    def _on_seen_top(self, readings: Readings) -> bool:
        """Whether the fingertips are at the seen top, neither past it nor OVER_SEEN_TOP over it:
        what a jaw meets there is that top."""
        return self._at_seen_top(readings) and \
            float(readings.tcp[2, 3]) - self.reach < self.seen_top + OVER_SEEN_TOP

    def _turn(self, readings: Readings) -> None:
        """Turn the jaws a quarter turn about the vertical, the way that leaves the last arm
        joint more room (`roll_room`, that joint turning `wrist_roll` times the turn, as the
        factory says), rise, and come down again where the search is centred: the moves across
        start afresh along the new closing axis."""
        self.turned = True
        info = self.ctx.info
        room = roll_room(readings.arm_q, info.arm_lower, info.arm_upper, self.wrist_roll)
        turn = -TURN if room is not None and room(-TURN) > room(TURN) else TURN
        self.rotation = about_vertical(turn) @ self.rotation
        self.shifts, self.bracket, self.hint = 0, Bracket(), None
        self._rise(readings, self.centre - readings.tcp[:3, 3], self._above_object())

    def _contact_across(self, readings: Readings, wrench: np.ndarray) -> np.ndarray | None:
        """(x, y, 0) in the hand frame of the contact point: where the contact force's line of
        action (from the wrist's force and torque, taken about the sensor `wrist_to_tcp` above
        the TCP) crosses the object's top as the task believes it, or the TCP's height; across
        the jaws, for a ball met by jaws without tactile images, where its centre lies
        (`BallUnderJaws.centre_across`): the contact is a finger's edge on its flank."""
        top = self._object_top()
        depth = self.wrist_to_tcp + (self._depth(readings.tcp[:3, 3]) - top if np.isfinite(top) else 0.0)
        lever = contact_across(wrench, depth)
        if lever is None or self.ball is None:
            return lever
        tips = float(readings.tcp[2, 3]) - self.tip_depth
        return np.array([lever[0], self.ball.centre_across(float(lever[1]), float(wrench[1]), tips), 0.0])

    def _close_here(self, readings: Readings, back_off: float, touching: bool = False) -> None:
        """Close with the TCP `back_off` back from here; `touching`: the hand rests on something."""
        if self.spannable:
            self._start_span(readings, back_off, touching)
            return
        self.goal = readings.tcp[:3, 3] + back_off * self.back
        self.phase = JawPhase.CLOSE
        self.risen = 0.0  # m the arm has risen in this close to take the hand off the support
        self.rim.reset()
        self.ctx.blackboard.contact = True

    def _start_span(self, readings: Readings, back_off: float, touching: bool) -> None:
        """Before the first close of a descent, asked to locate the object with a range sensor
        along the approach axis: along the jaws' width, as far as the object could be held
        from their middle (a jaw's half width and the object's widest), first one way, then
        the other, until the beam has seen both edges of its top (`primitives.arm.jaw_span`);
        the jaws then close there. A hand resting on something sweeps with its fingertips
        risen clear of the object's top (a jaw on a turned box's corner dragged it along and
        turned it) and comes down to the grasp's height to close (closing where the jaw had
        rested, they met over the box's top)."""
        self.spannable = False
        here = readings.tcp[:3, 3]
        fallback = here + back_off * self.back  # where the jaws were to close
        # where they close once the sweep has seen the object: there, or, for a hand that rested
        # on its edge, as deep as the grasp goes, the sweep having left the jaws either side of it
        close = self._at_depth(fallback, self._grasp_height()) if touching else fallback
        clear = self._object_top() + self.tip_depth + FLOOR_CLEARANCE if touching else -np.inf
        origin = self._at_depth(fallback, max(self._depth(fallback), clear))
        axis = unit(self._level(readings.tcp[:3, 0]))
        reach = self.jaw_half_width + self.ctx.object.widest
        route = [origin] + [self.walls.inside(self.rotation, origin + side * reach * axis, here)
                            for side in (1.0, -1.0)] + [origin, fallback]
        self.sweep = Sweep(origin, close, fallback, axis, route, BeamSpan(self.ctx.object.half_height))
        self.move_stall.reset(readings.time)
        self.phase = JawPhase.SPAN

    def _span(self, readings: Readings, dt: float) -> np.ndarray:
        """The sweep's next tick (the beam's range changes little as the hand rises or comes
        down, and jumps only at an edge): once the top's middle is seen, over it and down to
        the close's depth; with the sweep over (or stalled) and no middle seen, back where it
        began; there, the jaws close. A sweep that meets something (the wrist, tared as the
        descent began, in free air) pushes it: it goes back and the jaws close where they were
        to, the object not located; coming down, a contact is where the jaws close, the object
        located only if they are within a pad's half height of the grasp's height (held by its
        top, a box hung 5 cm under the hand and tipped over as it was put down: PyBullet)."""
        position = readings.tcp[:3, 3]
        sweep = self.sweep
        self.contact.update(readings, dt)
        goal = sweep.route[0]
        down = self._depth(goal) < self._depth(sweep.origin) - ARRIVED
        if sweep.risen and self.contact.force >= self.threshold:
            if down:  # on the object's edge: a grip this far above the grasp's height holds it by its top
                high = self._depth(position) - self._depth(sweep.close) > self.pad_half_height
                self._close_span(readings, self.back_off, located=not high)
                return np.zeros(3)
            if not sweep.met:
                sweep.blocked()
                goal = sweep.route[0]
        if sweep.looking and readings.range is not None and sweep.look(position, float(readings.range)):
            goal = sweep.route[0]
            self.move_stall.reset(readings.time)
        if norm(goal - position) < ARRIVED or self.move_stall.stalled(norm(goal - position), readings.time):
            sweep.risen = True
            if len(sweep.route) > 1:
                sweep.route.pop(0)
                self.move_stall.reset(readings.time)
                return np.zeros(3)
            self._close_span(readings, 0.0)
            return np.zeros(3)
        return clamp_norm(GAIN * (goal - position), SPAN_SPEED)

    def _close_span(self, readings: Readings, back_off: float, located: bool = True) -> None:
        """The sweep is over: the jaws close, and the place is told whether over the object's middle."""
        if located and self.sweep.located:
            self.ctx.memory[LOCATED_ALONG] = True
        self._close_here(readings, back_off)

    def _relieve(self, readings: Readings, dt: float) -> bool:
        """Rise while the wrist is pushed up beyond the empty hand's load: jaws squeezing an object
        below its widest point press it into the table, and the hand with it, and a lift tared on
        that reads its going as a collision (docs/constants.md). True once nothing presses (or the
        arm has risen MAX_RELIEF)."""
        empty = self.ctx.memory.get(EMPTY_HAND)
        pressed = 0.0 if empty is None else float(world_load(readings)[2] - empty[2])
        if pressed <= PRESSED or self.risen >= MAX_RELIEF:
            return True
        rise = min(RELIEF_GAIN * (pressed - PRESSED), self.speed) * dt
        self.goal = self.goal + rise * UP
        self.risen += rise
        return False

    def _felt_hint(self, readings: Readings, brushed: float | None) -> np.ndarray | None:
        """Where to look after jaws that met the object at one side along their width and
        closed past it: a step beyond the pads' edge that brushed it (`brushed`, from
        `jaws_brushed`), else (from above) a step beyond where the wrist felt a finger's bare
        rim push it, no further than the search's furthest point. Once: where that leads to
        nothing, the search goes on as planned."""
        if self.brushed:
            return None
        lever = self.rim.lever() if self.vertical else None
        if brushed is not None:
            offset = float(np.sign(brushed)) * self.step
        elif lever is not None:
            offset = float(np.clip(lever + np.sign(lever) * self.step, -2.0 * self.step, 2.0 * self.step))
        else:
            return None
        self.brushed = True
        return readings.tcp[:3, 3] + self._searching(readings) * offset

    def _search_on(self, readings: Readings, why: str = "the jaws closed on nothing") -> None:
        """Rise and go where the last contact placed the object (`hint`), else to the next
        search point; with none left, fail, saying `why`."""
        if self.hint is not None:
            point, self.hint, self.hinted = self.hint, None, True
        elif self.searched < len(self.offsets):
            point = self.centre + self._searching(readings) * self.offsets[self.searched]
            self.searched += 1
        else:
            self.phase = JawPhase.HOLD
            self.finish(Status.ERROR, f"{why} at {self.searched + self.hinted + self.turned + 1} points")
            return
        self._rise(readings, point - readings.tcp[:3, 3], self._above_object())

    def _close(self, readings: Readings, dt: float) -> np.ndarray:
        board = self.ctx.blackboard
        self.rim.add(self.contact.update(readings, dt))
        if board.jaws_empty and board.jaws_rim is not None:
            board.contact = False
            self._start_along(readings, board.jaws_rim)
            return np.zeros(3)
        if board.jaws_empty:
            board.contact = False
            if self.hint is None:
                self.hint = self._felt_hint(readings, board.jaws_brushed)
            self._search_on(readings)
            return np.zeros(3)
        nudge = board.arm_nudge
        if nudge is None:
            return np.zeros(3)
        nudged = self.goal + np.asarray(nudge, float) * dt
        # Inside the known walls like every other move: an object against a wall draws the
        # re-centring after it, and the goal, growing without bound, pressed the hand into the
        # wall at 190-270 N until the grasp's time ran out (Melfa, MuJoCo, docs/empty-the-box.md).
        kept = self.walls.inside(self.rotation, nudged, self.goal)
        self.goal = kept
        return np.asarray(nudge, float) if np.array_equal(kept, nudged) else np.zeros(3)

    def _start_along(self, readings: Readings, felt: float) -> None:
        """The jaws reopen from a grip the pads took only part of: the object lies between them
        beyond a pad's edge, on the side where the weaker pad felt it at its edge (`felt`),
        or else (from above) where the rim's lever says the close pushed it; along the hand's x,
        the pads' width, also for a grasp from the side. A pad's half width that way puts
        a contact on the rim (within the jaw's half width) on the pad. With neither, the jaws
        close again where they are."""
        lever = self.rim.lever() if self.vertical else None
        side = float(np.sign(felt)) if felt else 0.0 if lever is None else float(np.sign(lever))
        self.alongs += 1
        if LOCATED_ALONG in self.ctx.memory:  # the jaws leave the middle the sweep saw
            self.ctx.memory[LOCATED_ALONG] = False
        here = readings.tcp[:3, 3]
        # inside the known walls like every other move: one along into a wall wedged the hand (docs/empty-the-box.md)
        self.goal = self.walls.inside(self.rotation, here + readings.tcp[:3, 0] * side * self.pad_half_width, here)
        if side and norm(self.goal - here) < ARRIVED:
            self.goal = here.copy()  # a wall leaves no room along: the jaws would close as they did
            self._search_on(readings, "the jaws met the object beyond a pad's edge, a wall leaving no room along them")
            return
        self.move_stall.reset(readings.time)
        self.phase = JawPhase.ALONG

    def _along(self, readings: Readings) -> np.ndarray:
        """Along the jaws' width to `goal` while they open; there, or blocked, close again."""
        position = readings.tcp[:3, 3]
        if self.move_stall.stalled(norm(self.goal - position), readings.time) or (
                norm(self.goal - position) < ARRIVED and not self.ctx.blackboard.jaws_empty):
            self._close_here(readings, 0.0)
            return np.zeros(3)
        return clamp_norm(GAIN * (self.goal - position), self.speed)
