"""Grasps of three-finger hands: the hand side of the robust grasp (thesis 3.3.1; D5
appendix), and the naive baseline grasp of thesis 3.4.1 it is measured against.

The robust grasp: preshape, wait for the arm to find the object (blackboard CONTACT),
close every grasping finger until it can close no further, then judge the grasp by the
pads:

- every grasping finger touches, but unevenly by D5's finger-extension criterion (its
  quality Q at or above `stable_quality`, or two fingers on one side at extensions that
  turn the hand by `alpha_threshold` or more): reopen, move the hand by D5's position
  and orientation corrections (`extension.ExtensionGauge`), close again;
- every grasping finger touches: force adaptation raises each finger's effort until its
  pad feels GRASP_FORCE (a pinch's two fingers: one effort, until their pads' mean does);
  the grasp succeeds only then, with the object held; a pinch first lifts the object
  WEIGH_LIFT off the table and feels on the wrist (less the hand's own weight) where its
  weight hangs: more than OFF_CENTRE off the pinch line, turning the object about it
  harder than friction over a small contact carries (RIM_CONTACT), it sets it down,
  reopens and closes again that far across;
- some fingers touch and others closed on nothing (finger lost): reopen and ask the arm
  to shift the hand towards the fingers that touched, then close again (a shift back the
  way the last one came is a step of the search across the pinch line instead: the
  fingers take turns on the object's edge, so it lies off the line between them);
- no finger touches, the fingers stopped as far apart as the object is wide (jammed on
  it beside their pads): where two fingers pinch, look a little to one side of the pinch
  line, then to the other (`NUDGE`);
- no finger touches, but some touched something on the way and others did not (the
  object pushed aside by the first finger to meet it): as for a finger lost, towards those;
- no finger touches, but both of a pinch's fingers felt the object on the way, off their
  line (pushed out sideways until it cleared them): close next with the line through
  where it went, half its footprint's length beyond where the pads last felt it;
- no finger touches (object lost; known as soon as the pads pass within PASSED of the
  task's object's least width of each other): where two fingers pinch, the object lies off the line
  they close along, so search across it, one side then the other (`search_step`), and
  on the side a search step went as long as its close meets the object's edge; other
  hands take D5's security reflex: reopen, move a little further along the approach,
  close again;
- while holding, a grasping pad feels nothing for LOST_TIME while another presses (one
  finger has come off the object): as for a finger lost; every pad feels nothing (the
  object knocked away): as for an object lost;
- the pads never settle at GRASP_FORCE within SETTLE_LIMIT: an error naming the pads
  (D5's check of the grasped faces backs off 5 mm and closes again; that second hold
  would take the grasp past the 20 s a task gives it).

All corrections share one budget (RETRIES); once it is spent the grasp ends in an error
saying what went wrong last, with the pad forces where they matter.

Where each finger stands on the palm (`PadInfo.base`, from the robot's description) is
all the finger-lost correction needs to know which way "towards the contacts" is.
"""

from __future__ import annotations

from abc import abstractmethod
import numpy as np

from atd.model.frames import GRAVITY
from primitives.arm.motion import SUPPORT_BAND
from primitives.base import Context, ControlData, Controller, HandCommand, Status
from primitives.blackboard import CONTACT, EMPTY_HAND, FINGERS_STOPPED, PRESHAPED, PRESSING, SHIFT, WEIGH
from primitives.filters import LowPass, held_wrench, world_load
from primitives.hands.extension import ExtensionGauge, contact_points
from primitives.hands.posture import Stillness
from primitives.robot import HandMode, Readings
from primitives.search import search_offsets

CLOSING_SPEED = 0.3  # of each DOF's speed limit
# of each DOF's speed limit, opening: at the closing speed a Barrett took 4 s to reopen after
# closing on nothing, so a grasp had time for two attempts in the 20 s the examples give it
OPENING_SPEED = 1.0
LEAD = 0.05  # of a DOF's range: how far a closing finger's reference may run ahead of it
TOUCH_EFFORT = 0.05  # of the effort limit: a light touch, the least force adaptation starts from
SETTLE_TIME = 0.1  # s every pad must feel the grasp force (HELD) before the object counts as held
ADAPT_GAIN = 0.05  # effort (fraction of the limit) per N of missing pad force, per s
HELD = 0.9  # the weakest grasping pad within 10 % of GRASP_FORCE: the object is held
STALL_TIME = 0.3  # s a finger may stand still before it counts as stopped
REACHED = 0.02  # of a DOF's range
# s the pad forces are averaged over before the hold is judged: a pad on a tilted object
# can swing by +-3 N from one 5 ms tick to the next about a steady mean (PyBullet,
# grasp_and_lift seed 22), and force adaptation, an integrator, settles the mean only.
FELT_TIME = SETTLE_TIME
# s a hold may take to settle: with force adaptation starting from the closing's effort,
# measured holds settle in 0.2 to 2.5 s in PyBullet and 0.7 to 2.1 s in MuJoCo (both hands,
# both example grasps, seeds 0-4); one still unsettled at about 1.5 times the slowest never
# will. A grasp that cannot settle ends in its own error after one such hold: the Barrett
# pinching a box at 150 N did at 14.3 s (MuJoCo), where reopening, backing off and a second
# hold took it to 22.5 s, past the 20 s the examples give a grasp.
SETTLE_LIMIT = 4.0
RETRIES = 5  # corrections of any kind, per grasp
SEARCH_POINTS = 4  # points searched across the pinch line, about where the hand first closed
# s a grasping pad may feel nothing while another presses, in the hold: such holds waited
# out SETTLE_LIMIT and ended in an error, one pad at 0 N and the other at 8-15 N (SDH2,
# boxes, 20 of the robust grasp's 79 failures with the approach error in the preset at c06cbab)
LOST_TIME = 0.5
PINCHED = 2.0  # times the grasp force on every grasping pad: the fingers have closed on the object
# of the object's least width (the task's): pads that close this near each other without
# touching anything have nothing between them; closing on to the fingers' limits took the
# Barrett 1.1 and 2.9 s more in two empty closes (MuJoCo, the preset's duck trial 5 with the
# approach error); searching across its pinch line, it timed out in 18 and 15 of the preset's
# first 50 trials with the approach error (MuJoCo, PyBullet), 9 and 10 once it stopped here
PASSED = 0.5
FREE_RISE = 0.02  # m the arm rises to free a preshape blocked short of its posture
# of a pad's half width across its finger: the step across the pinch line when the fingers
# stopped on something beside their pads (`_jammed`)
NUDGE = 1.5
JAM_MARGIN = 0.005  # m beyond the object's widest that stopped fingers may stand apart on it
FELT_OFF_LINE = 0.003  # m off the pinch line the pads must last have felt an object to say which side it went
# m the robust grasp lifts what it holds to feel where its weight hangs, and how long (s) it
# feels it there: long enough for the swing of the lift's stop to die down
WEIGH_LIFT = 0.015
WEIGH_TIME = 0.2
# m the held weight may hang off the pinch line before the grasp sets it down and grasps it
# again across its centre of mass. The Barrett held the preset's mug by its rim, its weight
# 2.0 cm off the line, and it turned out of the hand 4 s after the lift (MuJoCo, mug trial 9
# with the approach error). Of the holds that lasted (trials 0-9), those furthest off the
# line hung 1.3-1.4 cm off on a curved face (a ball, a tape roll, the mug's trial 1), 2.2-2.7
# cm on a box's flat one: more of a flat face presses on the pads, to resist the turn
OFF_CENTRE = 0.015
# m: how far from its centre a pad's contact on a curved face carries friction against the
# turn: a weight whose torque about the pinch line friction over so small a contact carries
# at the pads' squeeze is held however far off the line it hangs (the 30 g duck, 2.6 cm off,
# 0.008 N m on pads at 9.4 N: MuJoCo, the preset's trial 13); the mug's trial 9 turned out
# of the hand with 0.018 N m on pads at 8.6 N, friction 0.6
RIM_CONTACT = 0.0015
GAP_CHECK = 0.05  # s between looks at the pads' gap (the hand's forward kinematics: 0.3-0.5 ms a look)


class FingerGrasp(Controller):
    """What every grasp of a multi-finger hand shares: which DOFs grasp (those the grasp
    posture moves), which pad each one's finger carries, and the phases preshape, wait
    for the arm's CONTACT, close, and hold; subclasses say how to close and how to hold."""

    def __init__(self, ctx: Context) -> None:
        super().__init__(ctx)
        hand = ctx.info.hand
        postures = hand.postures
        shapes = [s for s in (self.params.get("preshape"), self.params.get("grasp_shape")) if s is not None]
        for shape in shapes:
            if shape not in postures:
                raise ValueError(f"the hand cannot make the shape '{shape}'; it makes: {', '.join(sorted(postures))}")
        if self.params.get("grasp_shape") is None:
            raise ValueError("a multi-finger grasp needs grasp_shape")
        self.grasp = np.asarray(postures[self.params["grasp_shape"]], float)
        self.preshape = np.asarray(postures[self.params["preshape"]], float) if self.params.get("preshape") else None
        self.size = self.params.get("pregrasp_size")
        self.touch = float(self.params["contact_threshold"])
        self.range = hand.upper - hand.lower
        self.rate = CLOSING_SPEED * hand.velocity_limit
        self.stillness = Stillness(hand.velocity_limit, STALL_TIME)
        # A finger is known by its pad; a DOF belongs to the one finger whose pad it moves
        # (a spread that moves two fingers, and a palm pad no DOF moves, belong to none).
        self.pad_of = {pad.name: i for i, pad in enumerate(hand.pads)}
        self.finger_of_dof = [
            movers[0] if len(movers := [p.name for p in hand.pads if k in p.dofs]) == 1 else None
            for k in range(len(hand.dofs))
        ]

    # -- phases -------------------------------------------------------------------------
    def start(self, readings: Readings) -> None:
        hand = self.ctx.info.hand
        pre = readings.hand_q.copy() if self.preshape is None else self.preshape.copy()
        moving = (hand.closing != 0) & ~np.isclose(self.grasp, pre, atol=1e-4)
        if self.size is not None:  # open at least this far; closing past the preshape could catch the object
            sized = hand.closed + float(self.size) * (hand.open - hand.closed)
            wider = hand.closing * (pre - sized) > 0
            pre[moving & wider] = sized[moving & wider]
        self.pre, self.moving = pre, moving
        self.fingers = sorted({self.finger_of_dof[i] for i in np.flatnonzero(moving)} - {None})
        self.pinch = len(self.fingers) == 2  # two opposed fingers close on the object along one line
        self.reference = readings.hand_q.copy()
        self.effort = np.zeros_like(self.reference)
        self.pressing = moving  # the DOFs pressed by force once holding
        self.retries = 0
        self.phase = "preshape"
        self.stillness.start(readings.hand_q)
        self.ctx.blackboard[FINGERS_STOPPED] = False
        self.ctx.blackboard[PRESHAPED] = False
        self.ctx.memory[EMPTY_HAND] = world_load(readings)  # a grasp begins empty-handed
        if not self.fingers:
            self.finish(Status.ERROR, "from this posture the grasp shape moves no finger that has a tactile pad")
            self.phase = "failed"

    def update(self, readings: Readings, dt: float) -> ControlData:
        board = self.ctx.blackboard
        q = readings.hand_q
        if self.phase == "preshape":
            reached = self._ramp(self.pre, dt, q)
            if reached or (self._blocked(readings, dt) and not self._free_fingers(board)):
                self.phase = "wait"
                board[PRESHAPED] = True
        elif self.phase == "free" and board.get(SHIFT) is None:  # risen: preshape again, in free air
            self.phase = "preshape"
            self.stillness.seconds[:] = 0.0
            self.ctx.memory[EMPTY_HAND] = world_load(readings)
        elif self.phase == "wait" and board.get(CONTACT):
            self._begin_closing(board)
        elif self.phase == "close":
            self._close(readings, dt, board)
        elif self.phase == "reopen":
            if self._ramp(self.pre, dt, q, OPENING_SPEED / CLOSING_SPEED) or self._blocked(readings, dt):
                board[SHIFT] = self.shift
                self.phase = "shift"
        elif self.phase == "shift" and board.get(SHIFT) is None:
            self.retries += 1
            self._begin_closing(board)
        elif self.phase == "hold":
            self._hold(readings, dt)
        return self._command()

    def _free_fingers(self, board: dict) -> bool:
        """The preshape is blocked short of its posture: true if the arm is asked to rise
        so that the hand can make it in free air (phase "free"). The baseline grasp does not."""
        return False

    @abstractmethod
    def _close(self, readings: Readings, dt: float, board: dict) -> None:
        """One tick of closing; ends by setting FINGERS_STOPPED and the next phase."""

    @abstractmethod
    def _hold(self, readings: Readings, dt: float) -> None:
        """One tick of holding the object once the fingers have closed."""

    def _begin_closing(self, board: dict) -> None:
        self.phase = "close"
        self.stillness.seconds[:] = 0.0
        board[FINGERS_STOPPED] = False

    def _closed(self, readings: Readings, dt: float) -> bool:
        """One tick of closing: every grasping finger closes until it stands still (on the
        object, or blocked) or reaches its limit; true once all have. A pad touching on
        the way (a fingertip sliding on the table) does not stop a finger: only where the
        fingers end up counts, as a Barrett finger's clutch stops it only when blocked.
        While the arm's sliding grasp backs off a surface the fingertips press on
        (PRESSING), the fingers not yet on the object wait where they are: pressed on
        the table, they would stall there, short of the object."""
        hand = self.ctx.info.hand
        q = readings.hand_q
        waiting = self.moving & ~self._on_object(readings) if self.ctx.blackboard.get(PRESSING) else np.zeros_like(self.moving)
        closing = self.moving & ~waiting
        step = self.rate * dt
        self.reference[closing] += np.clip(hand.closed[closing] - self.reference[closing], -step[closing], step[closing])
        self.reference[waiting] = q[waiting]
        lead = LEAD * self.range  # how far the reference may run ahead of a blocked finger
        self.reference = np.clip(self.reference, q - lead, q + lead)
        at_limit = np.abs(q - hand.closed) < REACHED * self.range
        self._blocked(readings, dt)
        self.stillness.seconds[waiting] = 0.0
        return bool((at_limit | (self.stillness.seconds > STALL_TIME))[self.moving].all())

    def _on_object(self, readings: Readings) -> np.ndarray:
        """Per DOF: the pad of the finger it moves touches something."""
        pads = readings.pad_force
        return np.array([f is not None and pads[self.pad_of[f]] >= self.touch for f in self.finger_of_dof])

    def _touching(self, readings: Readings) -> list[str]:
        pads = readings.pad_force
        return [f for f in self.fingers if pads[self.pad_of[f]] >= self.touch]

    def _blocked(self, readings: Readings, dt: float) -> bool:
        """Counts how long each DOF has stood still (`Stillness`); true once every moving
        one has, for STALL_TIME (a preshape that meets the object stops there)."""
        return bool((self.stillness.update(readings.hand_q, dt)[self.moving] > STALL_TIME).all())

    # -- commands -----------------------------------------------------------------------
    def _ramp(self, goal: np.ndarray, dt: float, q: np.ndarray, faster: float = 1.0) -> bool:
        step = faster * self.rate * dt
        self.reference += np.clip(goal - self.reference, -step, step)
        return bool((np.abs(goal - q) < REACHED * self.range + 1e-3).all())

    def _command(self) -> ControlData:
        hand = self.ctx.info.hand
        pressing = self.pressing & (self.phase == "hold")
        values = np.where(pressing, hand.closing * self.effort, self.reference)
        modes = tuple(HandMode.FORCE if p else HandMode.POSITION for p in pressing)
        return ControlData(hand=HandCommand(values=values, modes=modes))


class RobustGraspHand(FingerGrasp):
    """The robust grasp's hand side, for any three-finger hand."""

    def __init__(self, ctx: Context) -> None:
        super().__init__(ctx)
        self.base = {pad.name: np.array(pad.base) for pad in ctx.info.hand.pads}
        self.grasp_force = float(self.params["grasp_force"])
        self.correct = bool(self.params["finger_lost_correction"])
        self.finger_lost_shift = float(self.params["finger_lost_shift"])
        self.object_lost_step = float(self.params["object_lost_step"])
        self.search_step = float(self.params["search_step"])
        self.extension_correction = bool(self.params["extension_correction"])
        self.stable_quality = float(self.params["stable_quality"])
        self.alpha_threshold = np.radians(float(self.params["alpha_threshold"]))

    def start(self, readings: Readings) -> None:
        super().start(readings)
        self.plan = search_offsets(self.search_step, SEARCH_POINTS)  # search points not yet visited
        self.across = 0.0  # m: where the hand closes across the pinch line, from where it first closed
        self.heading = 0.0  # the side (+1, -1) of a search step whose close is being judged, else 0
        self.lost_shift = np.zeros(3)  # the latest finger-lost correction's shift (hand frame)
        self.quality = np.inf  # D5's Q at the latest uneven grasp
        self.freed = False  # the arm has risen to free a blocked preshape
        self.nudged = 0  # nudges made across the pinch line after a jam: 0, then 1 (one side), -1 (both)
        self.jammed = False  # the latest close stopped on something beside the pads
        self.weighing: str | None = None  # lifting what it holds and weighing it ("up"), or setting it down ("down")
        if self.fingers:
            self.gauge = ExtensionGauge(self.ctx.info.hand, [self.pad_of[f] for f in self.fingers], self.pre)

    def _free_fingers(self, board: dict) -> bool:
        """Once per grasp: a preshape blocked short (fingertips pressed on the table as the
        spread turns) is made again FREE_RISE higher. Grasped from there, the Barrett's
        pinch closed with its fingers not facing each other and held the table (PyBullet,
        the preset's approach error, stapler 4: spread 0.72 rad of pi/2, pads 56 N)."""
        if self.freed:
            return False
        self.freed = True
        board[SHIFT] = np.array([0.0, 0.0, -FREE_RISE, 0.0])
        self.phase = "free"
        return True

    def _begin_closing(self, board: dict) -> None:
        super()._begin_closing(board)
        self.pinched = 0.0
        self.brushed: set[str] = set()  # the fingers whose pads touched something on the way
        self.felt_at = 0.0  # m across the pinch line: where the pads last felt the object on the way
        self.felt_by: set[str] = set()  # the fingers whose pads felt something above the table on the way
        self.looked = -np.inf  # when the pads' gap was last looked at

    def _close(self, readings: Readings, dt: float, board: dict) -> None:
        touching = self._touching(readings)
        self.brushed.update(touching)
        if touching and self.pinch:
            self._feel_across(readings, touching)
        if self._closed(readings, dt) or self._pinching(readings, dt, board) or self._passed(readings):
            self.jammed = self._jammed(readings)
            board[FINGERS_STOPPED] = True
            self.effort = self._starting_effort(readings)
            self.settled = 0.0
            self._judge(readings)

    def _pinching(self, readings: Readings, dt: float, board: dict) -> bool:
        """Every grasping pad has pressed on the object with PINCHED times the grasp force for SETTLE_TIME:
        the fingers have closed on it, though they could still creep on. Closing on past
        that squeezes a round object low on its side, where the squeeze pushes the hand up;
        the sliding grasp read that as the table and backed off, and the fingertips rode
        up and over the object (a ball and the duck, Barrett, PyBullet: 20 N on both pads,
        then nothing; 9 of 10 failed grasps without added error in the preset at 1df1356).
        Not while the arm backs off the surface: fingertips pressed on the table read
        the same."""
        pads = readings.pad_force
        pressed = all(pads[self.pad_of[f]] >= PINCHED * self.grasp_force for f in self.fingers)
        self.pinched = self.pinched + dt if pressed and not board.get(PRESSING) else 0.0
        return self.pinched >= SETTLE_TIME

    def _passed(self, readings: Readings) -> bool:
        """The pads have closed past the object's least width (PASSED of it) and touch
        nothing: there is nothing between the fingers, whatever is left of the close."""
        if self._touching(readings) or self.ctx.object is None or readings.time - self.looked < GAP_CHECK:
            return False
        self.looked = readings.time
        return self.gauge.gap(readings.hand_q) < PASSED * self.ctx.object.least_width

    def _jammed(self, readings: Readings) -> bool:
        """The fingers stopped short of their limits as far apart as the object is wide, and
        no pad feels anything: they stand on it beside their pads. A flat finger touches a
        cylinder at the foot of its axis, so a steel weight 11 mm off the SDH2's pinch line
        jammed both fingers on the 2 mm of each finger's face its 18 mm pad leaves bare
        (PyBullet, the preset's approach error, weight trials 9, 12, 14, 16)."""
        hand, q = self.ctx.info.hand, readings.hand_q
        short = np.abs(q - hand.closed) >= REACHED * self.range
        if self._touching(readings) or self.ctx.object is None or not short[self.moving].all():
            return False
        return PASSED * self.ctx.object.least_width <= self.gauge.gap(q) <= self.ctx.object.widest + JAM_MARGIN

    def _starting_effort(self, readings: Readings) -> np.ndarray:
        """Where force adaptation starts: each finger stopped on the object pressing with
        some effort, which its pad felt as some force; at rest a pad's force grows with the
        effort behind it, so that effort scaled to the grasp force is close to the one that
        holds it (SDH2: 2.0 N m gave 14 N in PyBullet, and 0.62 N m holds 4.6 N). Starting
        from a light touch instead, the integrator took 3 to 5.5 s to climb back up. Every
        finger starts from the least of these: opposed fingers pressing unequally push the
        object aside (a box slid out of the SDH2's pinch in PyBullet at 0.73 against 0.66)."""
        hand = self.ctx.info.hand
        pads, pressed = readings.pad_force, np.maximum(0.0, hand.closing * readings.hand_effort)
        touch = TOUCH_EFFORT * hand.effort_limit
        scaled = [pressed[i] * self.grasp_force / pads[self.pad_of[f]] / hand.effort_limit[i]
                  for i in np.flatnonzero(self.moving)
                  if (f := self.finger_of_dof[i]) and pads[self.pad_of[f]] >= self.touch]
        share = min(scaled, default=0.0)  # of each DOF's effort limit
        return np.where(self.moving, np.clip(share * hand.effort_limit, touch, hand.effort_limit), 0.0)

    def _judge(self, readings: Readings) -> None:
        """Every grasping finger on the object: hold it. Otherwise correct, towards the
        fingers that touch it; when none does, towards those that touched something on the
        way and lost it (the object pushed aside by the finger that met it first), as long
        as some did not: that side is where the object went."""
        heading, self.heading = self.heading, 0.0
        touching = self._touching(readings)
        if not touching and set(self.fingers) - self.brushed:
            touching = [f for f in self.fingers if f in self.brushed]
        lost = [f for f in self.fingers if f not in touching]
        if not lost and self._uneven(readings):
            return
        if not lost:
            self.phase = "hold"
            self.holding = 0.0
            self.felt = LowPass(FELT_TIME)
            self.entered = np.inf  # the weakest pad's force when it last came into the band
            self.lost_for = 0.0
            return
        what = f"finger {', '.join(lost)} missed the object" if touching else "nothing between the fingers"
        if self._nudging(readings):
            self._try_again(self._nudge(), "the fingers stopped on something their pads do not feel")
        elif touching and not self.correct:
            self._fail(what)
        elif touching and heading and self.pinch:
            # A search step's close met the object's edge: it lies further that way.
            self._try_again(self._search_step(beyond=heading), what)
        elif touching:  # finger lost: shift towards the fingers that touched
            toward = np.mean([self.base[f] for f in touching], axis=0) - np.mean([self.base[f] for f in lost], axis=0)
            shift = np.array([*toward / np.linalg.norm(toward), 0.0]) * self.finger_lost_shift
            if float(shift @ self.lost_shift) < 0.0:
                # Back the way the last one came: each finger in turn touches the object's
                # edge and the other misses, so the object lies off the line between them
                # (the SDH2 on a mug's side, 5.7 cm across its pinch line, flip-flopped
                # until its corrections ran out): look across that line instead.
                shift = self._search_step()
            self.lost_shift = shift
            self._try_again(shift, what)
        elif self._pushed_aside():
            self._try_again(self._after_pushed(), "the fingers pushed the object off their line")
        else:
            self._try_again(self._search_step(), what)

    def _uneven(self, readings: Readings) -> bool:
        """D5 3.3.3: every finger is on the object, but unevenly: correct, true if a
        correction is under way. D5 repeats the corrections until the grasp is stable;
        here the position correction only while each makes the grasp more even (Q
        falls): fingers that push the object as they close undo every move (a box in the
        Barrett's cylindrical grasp, PyBullet: pushed 2 cm towards the thumb at each
        close, Q 0.15 again and again). With no correction left to make, or the budget
        spent, the grasp holds what it has and the lift's events judge it."""
        if not self.extension_correction or self.retries >= RETRIES:
            return False
        check = self.gauge.check(readings)
        turn = check.turn if abs(check.turn) >= self.alpha_threshold else 0.0
        move = self.stable_quality <= check.quality < self.quality
        self.quality = check.quality
        if not move and turn == 0.0:
            return False
        shift = check.shift if move else np.zeros(3)
        what = f"uneven grasp (Q {check.quality:.3f}, alpha {np.degrees(turn):.1f} deg)"
        self._try_again(shift, what, turn)
        return True

    def _search_step(self, beyond: float = 0.0) -> np.ndarray:
        """Where to look next when the fingers closed on nothing (hand frame): across the
        pinch line, `search_step` to one side of where the hand first closed, then as far to
        the other, then twice as far each way (SEARCH_POINTS), then D5's step along the
        approach. Two closing fingertips sweep a narrow strip, and the seeds'
        approach error leaves the object up to 5 cm off it; D5's step down found nothing,
        the hand already on the table (Barrett, MuJoCo, the preset's approach error, trials
        0-2 of each object: 21 of 24 failures closed on nothing again and again). The steps
        are made at the surface: rising clear of the object and approaching again from above
        took so long that the grasp timed out after one step (6 of those 30 lifted, against
        10 this way).
        `beyond` (+1 or -1): the last step's close touched the object's edge on that side,
        so the next point is one step further that way, not the plan's next (the Barrett
        on a cylinder 5.3 cm off its line, MuJoCo, the preset's trial 1: a finger met it
        2.8 cm off, the plan went back the other way, and the grasp timed out)."""
        if not self.pinch or not (self.plan or beyond):
            return np.array([0.0, 0.0, self.object_lost_step])
        point = self.across + beyond * self.search_step if beyond else self.plan[0]
        self.plan = [p for p in self.plan if not np.isclose(p, point)]
        return self._look_across(point)

    def _feel_across(self, readings: Readings, touching: list[str]) -> None:
        """Where the touching pads feel something above the table, across the pinch line
        (m, hand frame, from the line through the fingers): each pad's centre of pressure,
        weighted by its force. Fingertips on the table say nothing of the object (the
        Barrett's, pressed on it in MuJoCo, turned the spread and read 4.8 cm off the line,
        the other side from the spray can they had pushed away: the preset's trial 9)."""
        pads = [self.pad_of[f] for f in touching]
        points = contact_points(self.ctx.info.hand, readings, pads)
        heights = points @ readings.tcp[2, :3] + readings.tcp[2, 3]  # world z
        above = heights >= SUPPORT_BAND
        if not above.any():
            return
        self.felt_by.update(f for f, up in zip(touching, above) if up)
        weights = readings.pad_force[pads] * above
        across = (points[:, :2] - self.base[self.fingers[0]]) @ self._normal()
        self.felt_at = float(weights @ across) / float(weights.sum())

    def _pushed_aside(self) -> bool:
        """Both pinching fingers felt the object on the way, then closed on nothing,
        where they last felt it off the pinch line: they pushed it out sideways. The closing
        fingertips of a Barrett meet a box's end on a slope and push it across their line
        until it clears them (a speaker, a stapler, a block: 4.5 cm off it); the search,
        which looks about where the hand first closed, 2.3 cm each side, pushed it out
        again at every close, and the grasp timed out (the preset's approach error, trials
        0-19: with this correction 151 -> 170 of 200 in PyBullet, 162 -> 178 in MuJoCo)."""
        return self._corrects_pinch() and set(self.fingers) <= self.felt_by and abs(self.felt_at) >= FELT_OFF_LINE

    def _after_pushed(self) -> np.ndarray:
        """The shift (hand frame) that closes next with the pinch line through the pushed
        object: beyond where the pads last felt it by half its footprint's length (pushed
        until it cleared the fingers, it reaches back to where they last touched it)."""
        side = float(np.sign(self.felt_at))
        return self._look_across(self.across + self.felt_at + side * self.ctx.object.footprint_length / 2.0)

    def _corrects_pinch(self) -> bool:
        """Two fingers pinch, corrections are on, and the task describes the object: what
        the corrections that reason from the object's size and weight need."""
        return self.pinch and self.correct and self.ctx.object is not None

    def _normal(self) -> np.ndarray:
        """The unit vector across the pinch line (hand frame x, y), the way a search step moves."""
        line = self.base[self.fingers[1]] - self.base[self.fingers[0]]
        return np.array([-line[1], line[0]]) / np.linalg.norm(line)

    def _look_across(self, point: float) -> np.ndarray:
        """The shift to a new place to look, `point` across the pinch line: its close is
        judged heading the way the step went, and no nudge has been made there yet."""
        self.nudged = 0
        self.heading = float(np.sign(point - self.across))
        return self._move_across(point)

    def _move_across(self, point: float) -> np.ndarray:
        """The shift (hand frame) that closes next at `point` across the pinch line, from
        where the hand first closed: the one place the search keeps track of where it is."""
        step, self.across = point - self.across, point
        return step * np.array([*self._normal(), 0.0])

    def _nudging(self, readings: Readings) -> bool:
        """No pad touches, and the pinch jammed (with neither side of it looked at yet) or
        its first nudge found nothing: look on (the other side)."""
        pending = (self.jammed and self.nudged == 0) or self.nudged == 1
        return self.pinch and self.correct and pending and not self._touching(readings)

    def _nudge(self) -> np.ndarray:
        """Where to look when the fingers jammed on the object beside their pads (hand
        frame): NUDGE pad half widths across the pinch line, then as far the other side of
        where they jammed; which side it lies is unknown."""
        width = max(self.ctx.info.hand.pads[self.pad_of[f]].half_size[1] for f in self.fingers)  # y: across the finger
        step = NUDGE * width * (1.0 if self.nudged == 0 else -2.0)
        self.nudged = 1 if self.nudged == 0 else -1
        self.heading = 0.0
        return self._move_across(self.across + step)

    def _try_again(self, shift: np.ndarray, what: str, turn: float = 0.0) -> None:
        """A failed attempt: reopen, have the arm make `shift` (hand frame) and `turn`
        (about the approach axis), close again.
        Every correction draws on one budget of RETRIES; once it is spent, the grasp
        fails saying `what` went wrong this last time."""
        if self.retries >= RETRIES:
            self._fail(what)
            return
        self.shift = np.array([*shift, turn])
        self.effort[:] = 0.0
        self.stillness.seconds[:] = 0.0
        self.phase = "reopen"

    def _fail(self, what: str) -> None:
        self.finish(Status.ERROR, f"{what} after {self.retries} corrections")
        self.phase = "failed"

    def _hold(self, readings: Readings, dt: float) -> None:
        """Force adaptation: from a light touch, each grasping finger's effort rises until
        its pad feels the grasp force, and keeps it there. The object is held once the
        weakest grasping pad has felt the grasp force (within 1 - HELD, averaged over
        FELT_TIME, and not drifting by more than that) for SETTLE_TIME. A pad force only
        falling through the band, as the squeeze left from closing bleeds off, is not held
        (MuJoCo, 8 N/s: 0.1 s in the band). A hold that has not settled within SETTLE_LIMIT
        is a failed grasp (the object tilted and wedged against the table, say): an error
        naming the pads.
        The two opposed fingers of a pinch share one squeeze instead, one effort driven and
        judged by their pads' mean (each pad touching: see LOST_TIME). Each finger's own
        loop pushed the object along the pinch line, the finger whose pad read less (its
        contact partly off the pad) closing on and on while the other gave way (SDH2,
        MuJoCo, the preset's approach error, wood 8: pads 1 and 8 N, the wood carried 8 cm
        off); a squeeze set by the weaker pad left pads at 4 and 9 N, still short of the
        band when SETTLE_LIMIT ran out (10 of the SDH2's 42 failures, MuJoCo, trials 0-19).
        Not every pad: opposed fingers share one squeeze, yet where the table takes part of
        it, or the fingers touch at different points, their pads read different forces, and
        a self-locking drive keeps its pad's force even at no effort, so all pads at the
        grasp force at once may never come. Not the strongest either: the squeeze left over
        from closing is above the grasp force on every pad until adaptation has let it go.
        Every grasping pad feeling nothing for LOST_TIME is the object gone (knocked over as
        the fingers closed): judged again at once, not after SETTLE_LIMIT."""
        hand = self.ctx.info.hand
        pads = readings.pad_force
        touching = self._touching(readings)
        self.lost_for = self.lost_for + dt if self.correct and len(touching) < len(self.fingers) else 0.0
        if self.lost_for >= LOST_TIME and self.status is Status.RUNNING:
            self.ctx.blackboard[WEIGH], self.weighing = None, None  # dropped while weighed: no more weighing
            self._judge(readings)
            return
        grasping = np.flatnonzero(self.moving)
        felt = np.array([pads[self.pad_of[f]] if (f := self.finger_of_dof[i]) else self.grasp_force for i in grasping])
        pressed = np.full_like(felt, felt.mean()) if self.pinch else felt
        limit = hand.effort_limit[grasping]
        self.effort[grasping] = np.clip(self.effort[grasping] + ADAPT_GAIN * limit * (self.grasp_force - pressed) * dt,
                                        0.0, limit)
        averaged = self.felt(felt, dt)
        if self.weighing is not None:
            self._weigh(readings)
            return
        squeeze = float(averaged.mean() if self.pinch else averaged.min())
        band = (1.0 - HELD) * self.grasp_force
        if abs(squeeze - self.grasp_force) > band or abs(squeeze - self.entered) > band:
            self.entered, self.settled = squeeze, 0.0  # out of the band, or only passing through it
        else:
            self.settled += dt
        self.holding += dt
        if self.status is not Status.RUNNING:
            return
        if self.settled >= SETTLE_TIME and self._corrects_pinch():
            self.weighing, self.weights = "up", []  # lift it, to feel where its weight hangs
            self.ctx.blackboard[WEIGH] = WEIGH_LIFT
        elif self.settled >= SETTLE_TIME:
            self.finish(Status.DONE, f"object held after {self.retries} corrections: {self._forces(pads)}")
        elif self.holding > SETTLE_LIMIT:
            what = f"pads never settled at {self.grasp_force:.1f} N within {SETTLE_LIMIT:.0f} s ({self._forces(pads)})"
            self._fail(what)

    def _weigh(self, readings: Readings) -> None:
        """One tick of weighing what the pinch holds (D5's corrections centre the object
        between the fingers; this centres its weight under them): lifted WEIGH_LIFT off the
        table, the wrist feels it for WEIGH_TIME. A weight hanging off the pinch line turns
        the object about it, which only friction over the pads' contacts resists: more than
        OFF_CENTRE off, and harder than friction over RIM_CONTACT carries, the hand sets it
        down and grasps it again that far across. Otherwise it is held, lifted."""
        board = self.ctx.blackboard
        if board.get(WEIGH) is not None:  # the arm is still raising or lowering the hand
            return
        if self.weighing == "down":  # set down again: grasp it across its centre of mass
            self.weighing = None
            self._try_again(self.regrasp, self.off_line)
            return
        self.weights.append(held_wrench(self.ctx.info.hand, readings))
        if len(self.weights) * self.ctx.info.control_period < WEIGH_TIME:
            return
        offset, torque = self._weight_off_line(readings, np.mean(self.weights, axis=0))
        squeeze = float(sum(readings.pad_force[self.pad_of[f]] for f in self.fingers))
        if abs(offset) <= OFF_CENTRE or abs(torque) <= (self.ctx.object.friction or 0.0) * squeeze * RIM_CONTACT:
            self.weighing = None
            self.finish(Status.DONE, f"object held after {self.retries} corrections, its weight "
                                     f"{abs(offset) * 100:.1f} cm off the pinch line: {self._forces(readings.pad_force)}")
            return
        self.off_line = f"its weight hung {abs(offset) * 100:.1f} cm off the pinch line"
        self.regrasp = self._look_across(self.across + offset)
        self.weighing = "down"
        board[WEIGH] = -WEIGH_LIFT

    def _weight_off_line(self, readings: Readings, load: np.ndarray) -> tuple[float, float]:
        """How far across the pinch line (m, along `_normal`) the held load's weight acts,
        and its torque (N m) about the line through the two pads' contacts. 0, 0 when the
        wrist feels less than half the object's weight (the table still carries it)."""
        hand = self.ctx.info.hand
        ends = contact_points(hand, readings, [self.pad_of[f] for f in self.fingers])
        line = ends[1] - ends[0]
        line /= max(float(np.linalg.norm(line)), 1e-9)
        down = readings.tcp[2, :3] * -1.0  # the world's down, in the hand frame
        weight = float(load[:3] @ down)
        if weight <= 0.5 * GRAVITY * (self.ctx.object.weight or 0.0):
            return 0.0, 0.0
        torque = float(line @ (load[3:] + np.cross(hand.wrist - ends[0], load[:3])))
        across = np.cross(down, line)  # a weight this way of the line turns it positively
        return torque / weight * float(across[:2] @ self._normal()), torque

    def _forces(self, pads: np.ndarray) -> str:
        """The grasping pads' forces, for a reason a user reads."""
        return ", ".join(f"{f} {pads[self.pad_of[f]]:.1f} N" for f in self.fingers)


class NaiveGraspHand(FingerGrasp):
    """The naive grasp's hand (thesis 3.4.1): close until every finger stops, then add a
    little effort (`squeeze`) to the fingers whose pads touch. No judging, no
    corrections, no force adaptation: only closing on nothing at all is an error."""

    def __init__(self, ctx: Context) -> None:
        super().__init__(ctx)
        self.squeeze = float(self.params["squeeze"])

    def _close(self, readings: Readings, dt: float, board: dict) -> None:
        if not self._closed(readings, dt):
            return
        board[FINGERS_STOPPED] = True
        touching = self._touching(readings)
        if not touching:
            self.finish(Status.ERROR, "nothing between the fingers")
            self.phase = "failed"
            return
        self.pressing = self.moving & np.array([f in touching for f in self.finger_of_dof])
        self.effort = np.where(self.pressing, self.squeeze * self.ctx.info.hand.effort_limit, 0.0)
        self.phase = "hold"
        self.finish(Status.DONE, f"closed; touching: {', '.join(touching)}")

    def _hold(self, readings: Readings, dt: float) -> None:
        """The squeeze stays as set."""
