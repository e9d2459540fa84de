"""The hand side of the robust grasp (thesis 3.3.1; D5 appendix) for any three-finger hand:
preshape, wait for the arm to find the object (`contact`), close every grasping finger
until it can close no further, then judge the close by the pads (`_judge`): hold and
adapt the force, or correct and close again. Its phases, the corrections and the trials
behind each constant are in docs/robust-grasp.md.

All corrections share one budget (RETRIES); once it is spent the grasp ends in an error
saying what went wrong last, with the pad forces where they matter.
"""

from __future__ import annotations

import numpy as np

from atd.model.frames import GRAVITY
from atd.model.vocabulary import ObjectClass
from primitives.arm.motion import SUPPORT_BAND
from primitives.base import Context, Status
from primitives.blackboard import EMPTY_HAND, STEEP_PINCH, Shift
from primitives.filters import WEIGHED, LowPass, held_wrench, world_load
from primitives.hands.extension import ExtensionGauge, contact_points, on_side_row
from primitives.hands.grasp_phases import Closing, Corrections, Holding, Phase, Weighing
from primitives.hands.force_grasp import ForceGrasp
from primitives.hands.multi_finger import CLOSING_SPEED
from primitives.hands.pinch_search import PinchSearch
from primitives.robot import Readings

OPENING_SPEED = 1.0  # of each DOF's speed limit: reopening at the closing speed left time for only two closes
SETTLE_TIME = 0.1  # s every pad must feel the grasp force (HELD) before the object counts as held
HELD = 0.9  # the squeeze within 10 % of the grasp force: the object is held
FELT_TIME = SETTLE_TIME  # s the pad forces are averaged over: a pad on a tilted object swings about a steady mean
SETTLE_LIMIT = 4.0  # s a hold may take to settle: 1.5 times the slowest measured; one unsettled then never will
RETRIES = 5  # corrections of any kind per grasp: room for a search and a regrasp within a task's 20 s
LOST_TIME = 0.5  # s a grasping pad may feel nothing while another presses before the finger counts as lost
PINCHED = 2.0  # times the grasp force on every grasping pad: closed on the object; closing on pushes a ball up
PASSED = 0.5  # of the object's least width: pads this near each other touching nothing have nothing between them
FREE_RISE = 0.02  # m the arm rises to free a preshape blocked on the table: clear of a fingertip's press
JAM_MARGIN = 0.005  # m beyond the object's widest that stopped fingers may stand apart on it
FELT_OFF_LINE = 0.003  # m off the pinch line the pads must last have felt the object to say which side it went
WEIGH_LIFT = 0.015  # m the pinch lifts what it holds to feel where its weight hangs: clear of the table
WEIGH_TIME = 0.2  # s it feels it there: the swing of the lift's stop dies down first
OFF_CENTRE = 0.015  # m the weight may hang off the pinch line: further, it turned out of the hand
RIM_CONTACT = 0.0015  # m over which a pad's contact on a curved face carries friction against the turn
FAR_OFF = 0.03  # m beyond which friction is not trusted: holds lasted to 2.9 cm off, one at 3.4 cm fell
ROLLING_CLOSE = 0.5  # of the closing speed, on a ball: a finger's edge meeting it at full speed kicks it away
GAP_CHECK = 0.05  # s between looks at the pads' gap: a look (forward kinematics) costs 0.3-0.5 ms
SLIPPED_GRIP = 2.0  # times the grasp force after the object slipped out of the pads as the arm lifted it


class RobustGraspHand(ForceGrasp):
    """The robust grasp's hand side, for any three-finger hand."""

    def __init__(self, ctx: Context) -> None:
        super().__init__(ctx)
        self.base = {pad.name: np.array(pad.base) for pad in ctx.info.hand.pads}
        self.correct = bool(self.params["finger_lost_correction"])
        self.finger_lost_shift = float(self.params["finger_lost_shift"])
        self.extension_correction = bool(self.params["extension_correction"])
        self.side_edge_correction = bool(self.params["side_edge_correction"])
        self.stable_quality = float(self.params["stable_quality"])
        self.alpha_threshold = np.radians(float(self.params["alpha_threshold"]))
        self.swing = float(self.params["closing_swing"])

    def start(self, readings: Readings) -> None:
        super().start(readings)
        self.ctx.memory.pop(STEEP_PINCH, None)
        self.corrections = Corrections()
        self.closing = Closing()
        thing = self.ctx.object
        self.round = thing is not None and thing.object_class is ObjectClass.SPHERE
        self.slowed = ROLLING_CLOSE if self.round else 1.0
        if self.fingers:
            hand = self.ctx.info.hand
            self.gauge = ExtensionGauge(hand, [self.pad_of[f] for f in self.fingers], self.pre)
            self.search = PinchSearch(self._normal() if self.pinch else None, float(self.params["search_step"]),
                                      float(self.params["object_lost_step"]),
                                      max(hand.pads[self.pad_of[f]].half_size[1] for f in self.fingers))

    # -- phases: one tick each ------------------------------------------------------------
    def _free(self, readings: Readings, dt: float) -> None:
        """Risen: preshape again, in free air, once the arm has made the rise."""
        if self.ctx.blackboard.shift is None:
            self.phase = Phase.PRESHAPE
            self.stillness.seconds[:] = 0.0
            self.ctx.memory[EMPTY_HAND] = world_load(readings)

    def _wait(self, readings: Readings, dt: float) -> None:
        """Told to close on a ball with a grasping pad on the table: first rise as far as the
        closing swings the fingertips down (`closing_swing`), once per grasp, and close in
        free air. Closed from there, the fingertips pressed on the table levered the hand up
        only as fast as the arm gave way: 6-8 s of the grasp's 20 for the Barrett's first close,
        which the ball's half-speed closes could not spare; on other objects the rise's second
        gained nothing (docs/robust-grasp.md, "The Barrett's first close levered up off the table")."""
        if self.round and self.ctx.blackboard.contact and self.swing > 0.0 and not self.corrections.lifted \
                and self._on_table(readings):
            self.corrections.lifted = True
            self.ctx.blackboard.shift = Shift(np.array([0.0, 0.0, -self.swing]))
            self.phase = Phase.FREE
            return
        super()._wait(readings, dt)

    def _close(self, readings: Readings, dt: float) -> None:
        touching = self._touching(readings)
        self.closing.brushed.update(touching)
        if touching and self.pinch:
            self._feel_across(readings, touching)
        if self._closed(readings, dt) or self._pinching(readings, dt) or self._passed(readings):
            self.corrections.jammed = self._jammed(readings)
            self.ctx.blackboard.fingers_stopped = True
            self.effort = self._starting_effort(readings)
            self._judge(readings)

    def _reopen(self, readings: Readings, dt: float) -> None:
        """Back to the preshape, fast; then the arm is asked for the correction's move, or
        first to lower the hand as far as it had lifted an object that slipped out of the pads."""
        if self._ramp(self.pre, dt, readings.hand_q, OPENING_SPEED / CLOSING_SPEED) or self._blocked(readings, dt):
            if self.closing.dropped is None:
                self._ask_for_shift()
            else:
                self._lower_back()

    def _lower_back(self) -> None:
        """The object slipped out of the pads as the arm lifted it to weigh it: the arm lowers
        the open hand as far as it had lifted, and every hold after presses SLIPPED_GRIP times
        the force asked: where the pads met it their friction did not carry its weight, and
        friction grows with the squeeze (docs/robust-grasp.md, "The Barrett beyond the preset
        at two fresh seeds")."""
        self.ctx.blackboard.weigh, self.closing.dropped = -self.closing.dropped, None
        self.grasp_force = SLIPPED_GRIP * float(self.params["grasp_force"])
        self.phase = Phase.LOWER

    def _lower(self, readings: Readings, dt: float) -> None:
        """Once the arm has lowered the open hand back: the correction's move."""
        if self.ctx.blackboard.weigh is None:
            self._ask_for_shift()

    def _ask_for_shift(self) -> None:
        """The hand open: the arm is asked for the correction's move."""
        self.ctx.blackboard.shift = self.corrections.shift
        self.phase = Phase.SHIFT

    def _shift(self, readings: Readings, dt: float) -> None:
        if self.ctx.blackboard.shift is None:  # the arm has made the move
            self.corrections.retries += 1
            self._begin_closing()

    def _hold(self, readings: Readings, dt: float) -> None:
        """Force adaptation until the squeeze settles at the grasp force (within 1 - HELD,
        averaged over FELT_TIME, and not only passing through the band) for SETTLE_TIME, or
        below it with every finger at its effort limit (`_strongest`); then a pinch weighs
        what it holds, other grasps are done. Unsettled after SETTLE_LIMIT: an error naming
        the pads."""
        averaged = self._squeeze(readings, dt)
        if averaged is None:
            return
        held = self.held
        squeeze = float(averaged.mean() if self.pinch else averaged.min())
        band = (1.0 - HELD) * self.grasp_force
        short = squeeze < self.grasp_force - band and self._strongest()  # steady there, it is all the hand has
        if (abs(squeeze - self.grasp_force) > band and not short) or abs(squeeze - held.entered) > band:
            held.entered, held.settled = squeeze, 0.0  # out of the band, or only passing through it
        else:
            held.settled += dt
        held.short = short
        held.holding += dt
        if self.status is not Status.RUNNING:
            return
        if held.settled >= SETTLE_TIME and self._corrects_pinch():
            # lift it, to feel where its weight hangs
            self.phase, self.weighing = Phase.WEIGH, Weighing(lifted_from=float(readings.tcp[2, 3]))
            self.ctx.blackboard.weigh = WEIGH_LIFT
        elif held.settled >= SETTLE_TIME:
            self.finish(Status.DONE, f"object held after {self.corrections.retries} corrections: "
                                     f"{self._forces(readings.pad_force)}{self._short_of()}")
        elif held.holding > SETTLE_LIMIT:
            what = (f"pads never settled at {self.grasp_force:.1f} N within {SETTLE_LIMIT:.0f} s "
                    f"({self._forces(readings.pad_force)})")
            self._fail(what)

    def _weigh(self, readings: Readings, dt: float) -> None:
        """Lifted WEIGH_LIFT by the arm, the wrist feels the held weight for WEIGH_TIME. More
        than OFF_CENTRE off the pinch line (or any distance, for a hold short of the grasp
        force: OFF_CENTRE was measured at it), and turning the object harder than friction
        over RIM_CONTACT carries or hanging beyond FAR_OFF, the arm sets it down (SET_DOWN)
        to grasp it again that far across; otherwise it is held, lifted. Not while a grasping
        pad feels nothing: the object slipping out of the pads as the arm raised them leaves
        the wrist feeling less than WEIGHED of it, which reads as centred (`_weight_off_line`),
        so the weighing waits until the pads hold it again or `_squeeze` finds it dropped
        (docs/robust-grasp.md, "Weighed as it slipped out")."""
        if self._squeeze(readings, dt) is None or self.ctx.blackboard.weigh is not None:
            return  # dropped, or the arm is still raising the hand
        if len(self._touching(readings)) < len(self.fingers):
            return
        weighing = self.weighing
        weighing.weights.append(held_wrench(self.ctx.info.hand, readings))
        if len(weighing.weights) * self.ctx.info.control_period < WEIGH_TIME:
            return
        offset, torque = self._weight_off_line(readings, np.mean(weighing.weights, axis=0))
        squeeze = float(sum(readings.pad_force[self.pad_of[f]] for f in self.fingers))
        near = abs(offset) <= OFF_CENTRE and not self.held.short
        carried = abs(offset) <= FAR_OFF and abs(torque) <= (self.ctx.object.friction or 0.0) * squeeze * RIM_CONTACT
        again = not (near or carried) and self._off_again(offset)
        self.corrections.weighed_off = offset
        if near or carried or again:
            self.phase = Phase.HOLD
            self.ctx.memory[STEEP_PINCH] = self._steep(readings) or self._beside(offset) or again
            self.finish(Status.DONE, f"object held after {self.corrections.retries} corrections, its weight "
                                     f"{abs(offset) * 100:.1f} cm off the pinch line: {self._forces(readings.pad_force)}"
                                     f"{self._short_of()}")
            return
        weighing.off_line = f"its weight hung {abs(offset) * 100:.1f} cm off the pinch line"
        weighing.regrasp = self.search.look(self.search.across + offset, weighed=True)
        self.phase = Phase.SET_DOWN
        self.ctx.blackboard.weigh = -WEIGH_LIFT

    def _off_again(self, offset: float) -> bool:
        """A regrasp across to the weight weighs it off the same side again, within FAR_OFF:
        the pinch meets the object at the same part wherever the hand moves (the bunny's
        widest part lies 2 cm from its weight, docs/robust-grasp.md "The Barrett's bunny
        weighed off its line again"), so a third close would only spend the grasp's time.
        It is held, watched like a flank pinch before the lift says so."""
        last = self.corrections.weighed_off
        return last * offset > 0.0 and abs(offset) <= FAR_OFF

    def _steep(self, readings: Readings) -> bool:
        """The pads stand closer than the object's least width W by more than friction
        allows (gap < W / hypot(1, mu)): on a round body they press faces turned from the
        squeeze line by acos(gap / W), past the friction angle, and the squeeze pushes it out
        of the fingertips, slowly. Where the body is not round (a duck's neck) such a pinch holds."""
        thing = self.ctx.object
        return self.gauge.gap(readings.hand_q) < thing.least_width / np.hypot(1.0, thing.friction or 0.0)

    def _beside(self, offset: float) -> bool:
        """The weight hangs beyond the pads' edge (more than the narrower pad's half-width
        off the pinch line): the pads hold the object by its flank, every face they press
        turned the same way from the squeeze, which pushes a round body out sideways, slowly
        (the Barrett's duck, docs/robust-grasp.md "A pinch held by the flank")."""
        hand = self.ctx.info.hand
        return abs(offset) > min(hand.pads[self.pad_of[f]].half_size[1] for f in self.fingers)

    def _set_down(self, readings: Readings, dt: float) -> None:
        """Once the arm has set the object down: grasp it again across its centre of mass."""
        if self._squeeze(readings, dt) is not None and self.ctx.blackboard.weigh is None:
            self._try_again(self.weighing.regrasp, self.weighing.off_line)

    # -- closing ------------------------------------------------------------------------
    def _free_fingers(self) -> bool:
        """Once per grasp: a preshape blocked short (fingertips pressed on the table as the
        spread turns) is made again FREE_RISE higher, where its fingers face each other."""
        if self.corrections.freed:
            return False
        self.corrections.freed = True
        self.ctx.blackboard.shift = Shift(np.array([0.0, 0.0, -FREE_RISE]))
        self.phase = Phase.FREE
        return True

    def _begin_closing(self) -> None:
        super()._begin_closing()
        self.closing = Closing()

    def _pinching(self, readings: Readings, dt: float) -> bool:
        """Every grasping pad has pressed on the object with PINCHED times the grasp force
        for SETTLE_TIME: the fingers have closed on it, though they could still creep on;
        closing on squeezes a round object low on its side up out of the hand. Not while
        the arm backs off the surface: fingertips pressed on the table read the same."""
        pads = readings.pad_force
        pressed = all(pads[self.pad_of[f]] >= PINCHED * self.grasp_force for f in self.fingers)
        self.closing.pinched = self.closing.pinched + dt if pressed and not self.ctx.blackboard.pressing else 0.0
        return self.closing.pinched >= SETTLE_TIME

    def _passed(self, readings: Readings) -> bool:
        """The pads have closed past the object's least width (PASSED of it) and touch
        nothing: there is nothing between the fingers, whatever is left of the close."""
        if self._touching(readings) or self.ctx.object is None or readings.time - self.closing.looked < GAP_CHECK:
            return False
        self.closing.looked = readings.time
        return self.gauge.gap(readings.hand_q) < PASSED * self.ctx.object.least_width

    def _jammed(self, readings: Readings) -> bool:
        """The fingers stopped short of their limits as far apart as the object is wide, and
        no pad feels anything: they stand on it beside their pads (a flat finger touches a
        cylinder at the foot of its axis, on the bare face beside its pad)."""
        q = readings.hand_q
        short = ~self._at_closed(q)
        if self._touching(readings) or self.ctx.object is None or not short[self.moving].all():
            return False
        return PASSED * self.ctx.object.least_width <= self.gauge.gap(q) <= self.ctx.object.widest + JAM_MARGIN

    def _feel_across(self, readings: Readings, touching: list[str]) -> None:
        """Where the touching pads feel something above the table, across the pinch line
        (m, hand frame, from the line through the fingers): each pad's centre of pressure,
        weighted by its force. Fingertips on the table say nothing of the object."""
        pads = [self.pad_of[f] for f in touching]
        points, above = self._above_table(readings, pads)
        if not above.any():
            return
        self.closing.felt_by.update(f for f, up in zip(touching, above) if up)
        weights = readings.pad_force[pads] * above
        across = (points[:, :2] - self.base[self.fingers[0]]) @ self.search.normal
        self.closing.felt_at = float(weights @ across) / float(weights.sum())

    def _above_table(self, readings: Readings, pads: list[int]) -> tuple[np.ndarray, np.ndarray]:
        """Where pads `pads` touch (hand frame), and per pad whether that is above the
        table (SUPPORT_BAND over the world's z = 0) rather than on it."""
        points = contact_points(self.ctx.info.hand, readings, pads)
        return points, points @ readings.tcp[2, :3] + readings.tcp[2, 3] >= SUPPORT_BAND

    def _pinched_table(self, readings: Readings, touching: list[str]) -> bool:
        """The close ended with every grasping pad pressed PINCHED times the grasp force on
        the table, none on anything above it: the fingertips pinched the table, not the
        object. Held as a grasp, that pinch never settled (the Barrett's stapler and mug:
        "pads never settled" at 20-35 N). A single pad that low is not told from one pressing
        an object's foot (docs/robust-grasp.md, "Pads that pinch the table")."""
        if self.closing.pinched < SETTLE_TIME or len(touching) < len(self.fingers):
            return False
        return not self._above_table(readings, [self.pad_of[f] for f in touching])[1].any()

    def _off_table(self, readings: Readings) -> np.ndarray:
        """The shift after the pads pinched the table: FREE_RISE up, clear of the fingertips'
        press, to close again there if the pads stood wide enough apart for the object to be
        between them (the table stopped them short of it), else to the search's next point."""
        rise = np.array([0.0, 0.0, -FREE_RISE])
        if self.ctx.object is not None and self.gauge.gap(readings.hand_q) >= PASSED * self.ctx.object.least_width:
            return rise
        return rise + self.search.next(side=self._felt_side())

    def _on_table(self, readings: Readings) -> bool:
        """A grasping pad touches the table."""
        pads = [self.pad_of[f] for f in self._touching(readings)]
        return bool(pads) and not self._above_table(readings, pads)[1].all()

    # -- judging a close ----------------------------------------------------------------
    def _judge(self, readings: Readings) -> None:
        """Every grasping finger on the object: hold it. Otherwise correct, towards the
        fingers that touch it; when none does, towards those that touched something on the
        way and lost it (the object pushed aside by the finger that met it first), as long
        as some did not: that side is where the object went; a ball one pad met off the line
        lies across it (`_rolled_aside`). A regrasp to the object's weighed
        weight that closes on nothing pushed it on: one step further that way. An object that
        slipped down out of the pads as the arm lifted it to weigh it stands where they held
        it: close again there, as low as they held it, not half its footprint beyond as after
        a push (the Barrett's bunny, sent 4.5 cm off it; docs/robust-grasp.md, "The bunny
        dropped in the weighing")."""
        search = self.search
        heading, search.heading = search.heading, 0.0
        weighed, search.weighed = search.weighed, False
        touching = self._touching(readings)
        if self._pinched_table(readings, touching):
            self._try_again(self._off_table(readings), "the pads pinched the table")
            return
        if not touching and set(self.fingers) - self.closing.brushed:
            touching = [f for f in self.fingers if f in self.closing.brushed]
        lost = [f for f in self.fingers if f not in touching]
        if not lost and (self._uneven(readings) or self._by_side_edges(readings)):
            return
        if not lost:
            self.phase, self.held = Phase.HOLD, Holding(LowPass(FELT_TIME))
            return
        what = f"finger {', '.join(lost)} missed the object" if touching else "nothing between the fingers"
        if self._nudging(readings):
            self._try_again(search.nudge(), "the fingers stopped on something their pads do not feel")
        elif touching and not self.correct:
            self._fail(what)
        elif touching and heading and self.pinch:  # a search step's close met the object's edge: further that way
            self._try_again(search.next(beyond=heading), what)
        elif touching and self._rolled_aside():  # a ball met by one pad off the line: across, that side
            self._try_again(self._after_pushed(), what)
        elif touching:  # finger lost: shift towards the fingers that touched
            toward = np.mean([self.base[f] for f in touching], axis=0) - np.mean([self.base[f] for f in lost], axis=0)
            shift = np.array([*toward / np.linalg.norm(toward), 0.0]) * self.finger_lost_shift
            if float(shift @ self.corrections.lost_shift) < 0.0:
                # Back the way the last one came: the fingers take turns on the object's
                # edge, so it lies off the line between them: look across that line instead.
                shift = search.next()
            self.corrections.lost_shift = shift
            self._try_again(shift, what)
        elif self.closing.dropped is not None and self._corrects_pinch():
            self._try_again(search.look(search.across + self.closing.felt_at),
                            "the object slipped out of the pads as the arm lifted it")
        elif self._pushed_aside():
            self._try_again(self._after_pushed(), "the fingers pushed the object off their line")
        elif heading and weighed and self.pinch:  # set down there a moment ago, and gone: pushed on that way
            self._try_again(search.onward(heading), what)
        else:
            self._try_again(search.next(side=self._felt_side()), what)

    def _uneven(self, readings: Readings) -> bool:
        """D5 3.3.3: every finger is on the object, but unevenly: correct, true if a
        correction is under way. The position correction only while each makes the grasp
        more even (Q falls): fingers that push the object as they close undo every move.
        With no correction left to make, or the budget spent, the grasp holds what it has
        and the lift's events judge it."""
        corrections = self.corrections
        if not self.extension_correction or corrections.retries >= RETRIES:
            return False
        check = self.gauge.check(readings)
        turn = check.turn if abs(check.turn) >= self.alpha_threshold else 0.0
        move = self.stable_quality <= check.quality < corrections.quality
        corrections.quality = check.quality
        if not move and turn == 0.0:
            return False
        shift = check.shift if move else np.zeros(3)
        what = f"uneven grasp (Q {check.quality:.3f}, alpha {np.degrees(turn):.1f} deg)"
        self._try_again(shift, what, turn)
        return True

    def _by_side_edges(self, readings: Readings) -> bool:
        """Both pinching pads press the object with their side edges only, on the same side
        of the pinch line: they meet the flank of a body standing beside them, the squeeze
        pushes it out sideways and the lift loses it (docs/robust-grasp.md, "Pinched by the
        pads' side edges"). Close again that far across, the line through where they pressed:
        true if that correction is under way; with the budget spent the grasp holds what it has.
        Not on a ball: the pads' edge contacts lie short of its centre (the correction left the
        SDH2's ball 1-2 cm off the line close after close, each squeeze and reopening rolling it
        on, until a close kicked it away), and a pad's face pressing it near its edge reads the
        same; the weighing measures where its weight hangs and grasps it again across that
        (docs/robust-grasp.md, "A ball pinched at the pads' edges")."""
        pads = [self.pad_of[f] for f in self.fingers]
        hand = self.ctx.info.hand
        if not (self.side_edge_correction and self._corrects_pinch()) or self.round \
                or self.corrections.retries >= RETRIES \
                or not all(on_side_row(hand, readings, k) for k in pads):
            return False
        across = (contact_points(hand, readings, pads)[:, :2] - self.base[self.fingers[0]]) @ self.search.normal
        if across[0] * across[1] <= 0.0:
            return False
        self._try_again(self.search.look(self.search.across + float(across.mean())),
                        "the pads pressed the object with their side edges only")
        return True

    def _pushed_aside(self) -> bool:
        """Both pinching fingers felt the object on the way, then closed on nothing, where
        they last felt it off the pinch line: they pushed it out sideways."""
        return set(self.fingers) <= self.closing.felt_by and self._felt_off_line() != 0.0

    def _felt_off_line(self) -> float:
        """The side of the pinch line (+1, -1) where a pad felt the object above the table,
        at least `FELT_OFF_LINE` off it, on the close just judged; 0 if none did."""
        closing = self.closing
        if not self._corrects_pinch() or not closing.felt_by or abs(closing.felt_at) < FELT_OFF_LINE:
            return 0.0
        return float(np.sign(closing.felt_at))

    def _rolled_aside(self) -> bool:
        """The pads felt a ball off the pinch line and a finger missed it: a ball between the
        fingers meets both, so it stood across the line on the side the pads felt it, and the
        touch rolled it on that way. D5's finger-lost shift along the line, towards the finger
        that touched, brings the line no nearer it; the SDH2 lost such balls to it
        (docs/robust-grasp.md, "A ball met by one pad"): look across, as after a push."""
        return self.round and self._felt_off_line() != 0.0

    def _felt_side(self) -> float:
        """Where a pad felt the object (`_felt_off_line`) on a close that ended with nothing
        between the fingers: a first close from the table that brushed the object with one
        pad, or swept it along, left it beyond that pad's edge, so the search looks that side
        first (docs/robust-grasp.md, "The Barrett's first search step, chosen by the pads").
        Not on a ball, whose edge contacts lie short of its centre (`_by_side_edges`)."""
        return 0.0 if self.round else self._felt_off_line()

    def _after_pushed(self) -> np.ndarray:
        """The shift (hand frame) that closes next with the pinch line through the pushed
        object: beyond where the pads last felt it by half its footprint's length (pushed
        until it cleared the fingers, it reaches back to where they last touched it)."""
        felt_at = self.closing.felt_at
        side = float(np.sign(felt_at))
        return self.search.look(self.search.across + felt_at + side * self.ctx.object.footprint_length / 2.0)

    def _corrects_pinch(self) -> bool:
        """Two fingers pinch, corrections are on, and the task describes the object: what
        the corrections that reason from the object's size and weight need."""
        return self.pinch and self.correct and self.ctx.object is not None

    def _normal(self) -> np.ndarray:
        """The unit vector across the pinch line (hand frame x, y), the way a search step moves."""
        line = self.base[self.fingers[1]] - self.base[self.fingers[0]]
        return np.array([-line[1], line[0]]) / np.linalg.norm(line)

    def _nudging(self, readings: Readings) -> bool:
        """No pad touches, and the pinch jammed (with neither side of it looked at yet) or
        its first nudge found nothing: look on (the other side)."""
        pending = self.search.nudge_pending(self.corrections.jammed)
        return self.pinch and self.correct and pending and not self._touching(readings)

    def _try_again(self, shift: np.ndarray, what: str, turn: float = 0.0) -> None:
        """A failed attempt: reopen, have the arm make `shift` (hand frame) and `turn`
        (about the approach axis), close again; once RETRIES are spent, fail saying `what`
        went wrong this last time."""
        if self.corrections.retries >= RETRIES:
            self._fail(what)
            return
        self.corrections.shift = Shift(np.array(shift, float), float(turn))
        self.effort[:] = 0.0
        self.stillness.seconds[:] = 0.0
        self.phase = Phase.REOPEN

    def _fail(self, what: str) -> None:
        self.finish(Status.ERROR, f"{what} after {self.corrections.retries} corrections")
        self.phase = Phase.FAILED

    # -- holding ------------------------------------------------------------------------
    def _squeeze(self, readings: Readings, dt: float) -> np.ndarray | None:
        """One tick of force adaptation, in every holding phase: from a light touch, each
        grasping finger's effort rises until its pad feels the grasp force; the two fingers
        of a pinch share one squeeze, driven by their pads' mean (`ForceGrasp._adapt`). The
        pad forces averaged over FELT_TIME; None once a grasping pad has felt nothing for LOST_TIME while another pressed (a
        finger off the object, or every one: knocked away), the close judged again."""
        touching = self._touching(readings)
        held = self.held
        held.lost_for = held.lost_for + dt if self.correct and len(touching) < len(self.fingers) else 0.0
        if held.lost_for >= LOST_TIME and self.status is Status.RUNNING:
            if self.phase is Phase.WEIGH:
                self.closing.dropped = float(readings.tcp[2, 3]) - self.weighing.lifted_from
            self.ctx.blackboard.weigh = None  # dropped while weighed: no more weighing
            self._judge(readings)
            return None
        felt = self._adapt(readings, dt)
        return held.felt(felt, dt)

    def _weight_off_line(self, readings: Readings, load: np.ndarray) -> tuple[float, float]:
        """How far across the pinch line (m, along `_normal`) the held load's weight acts,
        and its torque (N m) about the line through the two pads' contacts. 0, 0 when the
        wrist feels less than WEIGHED of the object's weight (the table still carries it)."""
        hand = self.ctx.info.hand
        ends = contact_points(hand, readings, [self.pad_of[f] for f in self.fingers])
        line = ends[1] - ends[0]
        line /= max(float(np.linalg.norm(line)), 1e-9)
        down = readings.tcp[2, :3] * -1.0  # the world's down, in the hand frame
        weight = float(load[:3] @ down)
        if weight <= WEIGHED * GRAVITY * (self.ctx.object.weight or 0.0):
            return 0.0, 0.0
        torque = float(line @ (load[3:] + np.cross(hand.wrist - ends[0], load[:3])))
        across = np.cross(down, line)  # a weight this way of the line turns it positively
        return torque / weight * float(across[:2] @ self.search.normal), torque

    def _short_of(self) -> str:
        """For a reason: a hold settled below the grasp force, as hard as the hand presses."""
        return f" (the hand's strongest squeeze, short of the {self.grasp_force:.1f} N asked)" if self.held.short else ""

    def _forces(self, pads: np.ndarray) -> str:
        """The grasping pads' forces, for a reason a user reads."""
        return ", ".join(f"{f} {pads[self.pad_of[f]]:.1f} N" for f in self.fingers)
