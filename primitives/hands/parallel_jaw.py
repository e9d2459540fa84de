"""Parallel-jaw grippers (Melfa's WRT-102, Baxter's gripper): two mirrored jaws on one DOF.

Thesis 7.3: the Melfa grasp closes until the tactile pads feel the grasp force, and the
transport keeps squeezing so the object does not loosen. The grip force comes from the
pads (the smaller of the two: both must press) or from the jaw motor's own effort.

Jaw layout, as `factories.parts.parallel_jaw` builds it: the jaws close along the hand's
y axis, the pad named `left...` on +y and `right...` on -y.
"""

from __future__ import annotations

import numpy as np

from primitives.base import Context, ControlData, Controller, HandCommand, Status
from primitives.blackboard import EMPTY_HAND
from primitives.filters import world_load
from primitives.hands.posture import position_command
from primitives.robot import HandMode, Readings

TOUCH = 0.5  # N on a pad: that finger touches the object
MOTOR_TOUCH = 0.25  # of the grasp force, on the jaw motor: the jaws meet resistance
CONFIRM = 0.95  # of the grasp force: the grip is there
SATURATED_GRIP = 0.7  # of the grasp force: as much as pads feel with the squeeze at its limit is a grip
NAIVE_SPEED = 0.5  # of the jaws' speed limit, for the naive grasp
EMPTY = 0.001  # m from fully closed: the jaws closed on nothing
STILL = 0.005  # m/s: jaws slower than this stand on the object (a motor's force alone is felt in motion too)
BLOCKED = 0.003  # m: still jaws this far short of their closing reference are held by the object
SQUEEZE_GAIN = 5.0  # 1/s: how fast the squeeze corrects the motor force towards the pad force wanted
SQUEEZE_TRIM = 0.5  # the correction stays within +-50 % of the grasp force
ALIGNED = 0.3  # of a pad's half width: a contact this near the pad's middle needs no move along the jaws
# s tactile jaws press with a pad feeling nothing before they count as closed on nothing (a touch reaches both in 0.1 s)
UNFELT_TIME = 0.5
# s a grip stays under SATURATED_GRIP with the squeeze at its limit before it counts as pressed through a
# finger's bare rim (the trim saturates within 0.3 s of pressing short by 5 N)
RIM_TIME = 0.5
RIM_MOVES = 2  # times per grasp the jaws reopen off a rim for the arm to move along their width
# of a pad's half width: a contact centred this far out lies in the pad's edge column (the Melfa's
# outer 3.4 mm), the rest of it on the finger's bare rim beyond
EDGE = 0.6
# s jaws stand still within EMPTY of closed before they count as shut: pressing off a lying can's
# axis squeezed it aside and the Baxter's paddles swept through 0.8 mm open in 40 ms, then sprang
# back to 4.8 mm on it, held, while the grasp had said "closed on nothing" (docs/empty-the-box.md)
SHUT_STILL = 0.1


class Jaws:
    """Reads a parallel gripper: grip force by pads or motor, which pad touches."""

    def __init__(self, ctx: Context, source: str) -> None:
        hand = ctx.info.hand
        if len(hand.dofs) != 1:
            raise ValueError(f"a parallel-jaw controller needs a one-DOF gripper; this hand has {len(hand.dofs)} DOFs")
        self.source = source
        self.closing = float(hand.closing[0])
        self.closed = float(hand.closed[0])
        sides = [1.0 if "left" in pad.name else -1.0 if "right" in pad.name else 0.0 for pad in hand.pads]
        if source == "tactile" and (len(sides) != 2 or sorted(sides) != [-1.0, 1.0]):
            raise ValueError("tactile grip force needs a 'left' and a 'right' finger pad; this hand has: "
                             + (", ".join(p.name for p in hand.pads) or "none"))
        self.sides = np.array(sides)

    def force(self, readings: Readings) -> float:
        if self.source == "tactile":
            return float(readings.pad_force.min())
        return max(0.0, self.closing * float(readings.hand_effort[0]))

    def both_touch(self, readings: Readings, grasp_force: float) -> bool:
        """Both jaws are on the object: both pads feel it, or the motor meets resistance."""
        if self.source == "tactile":
            return bool((readings.pad_force > TOUCH).all())
        return self.force(readings) > MOTOR_TOUCH * grasp_force

    def pad_unfelt(self, readings: Readings) -> bool:
        """Tactile pads, one of them or both touching nothing (a motor's force says nothing of where it pushes)."""
        return self.source == "tactile" and bool((readings.pad_force <= TOUCH).any())

    def empty(self, readings: Readings) -> bool:
        return abs(float(readings.hand_q[0]) - self.closed) < EMPTY

    def held(self, readings: Readings, reference: float) -> bool:
        """The jaws stand still short of the closing `reference`: something holds them."""
        lag = self.closing * (reference - float(readings.hand_q[0]))
        return lag > BLOCKED and abs(float(readings.hand_dq[0])) < STILL

    def command(self, force: float) -> ControlData:
        """Press the jaws together with `force` N."""
        return ControlData(hand=HandCommand(values=np.array([self.closing * force]), modes=(HandMode.FORCE,)))


class CloseUntilForce(Controller):
    """Close at `closing_speed` until both jaws touch, then press with `grasp_force`;
    done once the force source feels it (within 5 %).

    Pressing is done by force, not by driving the jaws further: a small object stops the
    jaws near their closed limit, where a position servo has no travel left to build
    force with. Re-centring: while only one pad touches, the object sits off-centre and
    closing further would push it across the table; the gripper asks the arm to move
    towards the touching pad as fast as that jaw closes, so the touching pad stands still
    on the object while the other comes to meet it.

    With an arm that corrects the approach (it raises `contact` when the jaws may close)
    the jaws wait for `contact`; closing on nothing is then no error: they say `jaws_empty`,
    reopen, and close again on the arm's next `contact`. They also stop closing while the
    pads feel the object off their middle along the jaws' width, and ask the arm to move
    that way first: a pad's rim closing on a round object pushes it aside. That move stops
    after `max_recentre`: a contact still off-centre by then moves with the pad (a slanted
    face pushed along), and following it would drag the object across the table. A grip is
    done only once that arm no longer rises off the support (`pressing`): until then, jaws
    that close empty say so and the arm looks again. Tactile jaws that press UNFELT_TIME with
    a pad feeling nothing stand on something beside that pad: closed on nothing too, the
    other pad, if it touches, saying which side the object is. Tactile jaws whose grip stays
    under SATURATED_GRIP for RIM_TIME with the squeeze at its limit press partly through a
    finger's bare rim beside the pads, as do jaws the squeeze counts as gripping only at its
    limit with the weaker pad's contact at its edge: they reopen too (at most RIM_MOVES times),
    saying where the weaker pad feels the object (`jaws_rim`), for the arm to move along the
    jaws' width until the pads take the push. Jaws count as closed on nothing only once they
    stand still within EMPTY of closed (SHUT_STILL): pressing off a lying can's axis squeezes it
    aside, and they sweep through on their way back onto it.
    """

    def __init__(self, ctx: Context, rim_moves: int = RIM_MOVES) -> None:
        super().__init__(ctx)
        self.grasp_force = float(self.params["grasp_force"])
        self.rim_moves_left = rim_moves  # reopenings off a rim left: 0 where the arm moves nothing along the jaws
        self.speed = float(self.params["closing_speed"])
        self.max_recentre = float(self.params["max_recentre"])
        self.jaws = Jaws(ctx, str(self.params["force_source"]))
        self.squeeze = Squeeze(ctx)  # presses on until the pads feel the force (a tilted grip loses some)
        # a motor cannot press harder than its effort limit: asked more, all it gives is the grip
        self.reachable = min(self.grasp_force, float(ctx.info.hand.effort_limit[0]))

    def start(self, readings: Readings) -> None:
        self.reference = self.opened = float(readings.hand_q[0])
        self.pressing = False
        self.recentred = 0.0  # m the arm has followed a contact along the jaws' width in this close
        self.brushed: float | None = None  # where along the jaws' width the pads last felt something in this close
        self.unfelt = 0.0  # s the jaws have pressed with neither pad feeling anything
        self.rimmed = 0.0  # s the jaws have pressed still, the squeeze at its limit, short of a grip
        self.ctx.memory[EMPTY_HAND] = world_load(readings)  # a grasp begins empty-handed
        self.guided = self.ctx.blackboard.contact is not None  # the arm says when to close
        self.shut_for = 0.0  # s the jaws have stood still within EMPTY of closed

    def update(self, readings: Readings, dt: float) -> ControlData:
        board = self.ctx.blackboard
        if self.guided and not self.pressing and not board.contact:
            return self._reopen(dt)
        if self.status is Status.RUNNING:
            force = self.jaws.force(readings)
            self.unfelt = self.unfelt + dt if self.pressing and self.jaws.pad_unfelt(readings) else 0.0
            self.rimmed = self.rimmed + dt if self._on_rim(readings, force) else 0.0
            # a motor pressing on its end stop feels force too; fingers stopped beside the pads grip nothing
            near = self.jaws.empty(readings)
            shut = self._shut_still(readings, near, dt)
            empty = shut or self.unfelt >= UNFELT_TIME
            gripped = (not near and not empty and self.pressing and abs(float(readings.hand_dq[0])) < STILL
                       and self._gripped(force) and not board.pressing)
            rim = None if near or empty else self._rim(readings, force, gripped)
            if empty:
                self.pressing = False
                self.brushed = self._across_pads(readings) or self.brushed  # a pad still touching says the side
                if self.guided:
                    board.jaws_empty = True
                    board.jaws_brushed = self.brushed
                else:
                    self.finish(Status.ERROR, "the jaws closed on nothing" if shut
                                else "the jaws stopped on something a pad does not feel")
            elif rim is not None:
                self.pressing, self.rimmed = False, 0.0
                self.rim_moves_left -= 1
                board.jaws_empty, board.jaws_rim = True, rim
            elif gripped:
                board.fingers_stopped = True
                limit = ", the squeeze at its limit" if force < CONFIRM * self.reachable else ""
                if self.reachable < self.grasp_force:
                    limit += f", the gripper gives {self.reachable:g} N"
                self.finish(Status.DONE, f"grip force {force:.1f} N (asked {self.grasp_force:g} N{limit})")
            elif not self.pressing and (self.jaws.both_touch(readings, self.grasp_force) or self._blocked(readings)):
                self.pressing = True
                self.squeeze.reset()  # each press starts from the grasp force
        if board.jaws_empty:
            return self._reopen(dt)
        if self.pressing:
            board.arm_nudge = None
            return self.squeeze.update(readings, dt)
        if self.status is Status.ERROR:
            board.arm_nudge = None
            return position_command(np.array([self.reference]))
        across = self._across_pads(readings)
        if across != 0.0:
            self.brushed = across
        off_centre = across if self.guided and self.recentred < self.max_recentre else 0.0
        self.recentred += abs(off_centre) * self.speed * dt
        closing = abs(off_centre) <= ALIGNED  # closing on a pad's rim pushes the object along the jaws' width
        board.arm_nudge = self._nudge(readings, off_centre, closing)
        if closing:
            self.reference += self.jaws.closing * self.speed * dt
        return position_command(np.array([self.reference]))

    def _shut_still(self, readings: Readings, near: bool, dt: float) -> bool:
        """Whether the jaws, within EMPTY of closed (`near`), have stood still there SHUT_STILL:
        jaws that sweep through it on an object squeezed aside are not shut."""
        self.shut_for = self.shut_for + dt if near and abs(float(readings.hand_dq[0])) < STILL else 0.0
        return self.shut_for >= SHUT_STILL

    def _gripped(self, force: float) -> bool:
        """The pads feel the grasp force, or all the jaw motor gives (its effort limit); or,
        with the squeeze's trim at its limit, most of it: a grip tilted by the approach error
        loads one pad more than the other, and the Melfa's pads held a tape roll at 17 and
        13 N, the motor at 150 %, until the grasp's timeout."""
        if force >= CONFIRM * self.reachable:
            return True
        return self.squeeze.saturated and force >= SATURATED_GRIP * self.grasp_force

    def _on_rim(self, readings: Readings, force: float) -> bool:
        """Tactile jaws pressing still on the object, both pads touching, the squeeze at its
        limit and the weaker pad still short of SATURATED_GRIP: the rest of the push goes
        through a finger's bare rim beside the pads (the Melfa's jaws stood at 10.0 and 10.7 N
        of 15 with the motor pressing 22.5 N of its 100 N; docs/robust-grasp.md)."""
        return (self.pressing and self.jaws.source == "tactile" and self.squeeze.saturated
                and abs(float(readings.hand_dq[0])) < STILL and not self.jaws.pad_unfelt(readings)
                and force < SATURATED_GRIP * self.grasp_force)

    def _rim(self, readings: Readings, force: float, gripped: bool) -> float | None:
        """Pressed partly through a finger's bare rim, with a reopening left for the arm to move
        along the jaws' width: where the weaker pad feels the object if at its edge (EDGE), else
        0; None where not. A grip held RIM_TIME under SATURATED_GRIP is on a rim, and so is one
        the squeeze counts only at its limit with the weaker pad's contact at its edge (the
        Melfa's grips at 10.5-11.1 N of 15 on a rim fell in the lift; docs/robust-grasp.md)."""
        if not (self.guided and self.pressing and self.rim_moves_left > 0):
            return None
        felt = self._pad_across(readings, int(np.argmin(readings.pad_force)))
        edge = felt if felt is not None and abs(felt) >= EDGE else 0.0
        if self.rimmed >= RIM_TIME or (gripped and force < CONFIRM * self.reachable and edge):
            return edge
        return None

    def _blocked(self, readings: Readings) -> bool:
        """Held short of where they are driven: near their closed stop a position servo has
        too little travel left to push as hard as a touch needs (a Baxter's paddles held a
        cylinder at 3.4 N of the 5 N, and waited out the grasp's timeout). Pressing by force
        then either grips or closes on nothing."""
        return self.jaws.held(readings, self.reference)

    def _reopen(self, dt: float) -> ControlData:
        """Back to the opening the grasp began with, at full speed (nothing is in the way);
        `jaws_empty` holds until it is reached."""
        board = self.ctx.blackboard
        board.arm_nudge = None
        if board.jaws_empty:
            self.reference -= self.jaws.closing * float(self.ctx.info.hand.velocity_limit[0]) * dt
            if self.jaws.closing * (self.reference - self.opened) <= 0.0:
                self.reference = self.opened
                self.recentred = 0.0
                self.brushed = None
                board.jaws_empty, board.jaws_rim = False, None
        return position_command(np.array([self.reference]))

    def _nudge(self, readings: Readings, off_centre: float, closing: bool) -> np.ndarray | None:
        """Along the jaws' width towards the contact, and towards the one touching pad while
        the jaws close: with the jaws paused, that move would push the object across the table."""
        if self.jaws.source != "tactile":
            return None
        touching = readings.pad_force > TOUCH
        if touching.sum() != 1 and off_centre == 0.0:
            return None
        nudge = readings.tcp[:3, 0] * (off_centre * self.speed)
        if touching.sum() == 1 and closing:
            nudge = nudge + readings.tcp[:3, 1] * (float(self.jaws.sides[touching][0]) * self.speed)
        return nudge

    def _across_pads(self, readings: Readings) -> float:
        """Where the touching pads feel the object along the jaws' width (the hand's x), from
        -1 to 1 of a pad's half width, weighted by their forces; 0 without a contact or
        tactile images."""
        where, weight = 0.0, 0.0
        for index, force in enumerate(readings.pad_force):
            at = self._pad_across(readings, index)
            if at is not None:
                where += at * force
                weight += force
        return where / weight if weight > 0.0 else 0.0

    def _pad_across(self, readings: Readings, index: int) -> float | None:
        """Where pad `index` feels the object along the jaws' width (the hand's x), from -1 to 1
        of its half width; None where it touches nothing or has no tactile image. The mirrored
        pads face each other, so the left pad's columns run along the hand's x and the right
        pad's against it (`factories.parts.parallel_jaw`)."""
        pad, force = self.ctx.info.hand.pads[index], float(readings.pad_force[index])
        image = readings.taxels.get(pad.name)
        if image is None or force <= TOUCH:
            return None
        columns = image.sum(axis=0)
        centre = float(columns @ np.arange(len(columns))) / float(columns.sum())
        return float(self.jaws.sides[index]) * ((centre + 0.5) / len(columns) * 2.0 - 1.0)


class Squeeze(Controller):
    """Keep pressing with `grasp_force` while the arm moves (thesis 7.3 transport).

    With the pads as force source, the motor force is trimmed until the pads feel the
    grasp force (within +-50 %: a pad that feels nothing must not drive the motor to its
    limit). Done at once: squeezing has no end of its own.
    """

    def __init__(self, ctx: Context) -> None:
        super().__init__(ctx)
        self.grasp_force = float(self.params["grasp_force"])
        self.jaws = Jaws(ctx, str(self.params["force_source"]))
        self.limit = SQUEEZE_TRIM * self.grasp_force  # N the trim may add or take away
        self.trim = 0.0

    def start(self, readings: Readings) -> None:
        self.finish(Status.DONE, f"squeezing with {self.grasp_force:g} N")

    def reset(self) -> None:
        """Press with the grasp force alone again (a new press begins)."""
        self.trim = 0.0

    @property
    def saturated(self) -> bool:
        """The motor already presses as hard as the trim allows."""
        return self.trim >= self.limit

    def update(self, readings: Readings, dt: float) -> ControlData:
        if self.jaws.source == "tactile":
            error = self.grasp_force - self.jaws.force(readings)
            self.trim = min(self.limit, max(-self.limit, self.trim + SQUEEZE_GAIN * error * dt))
        return self.jaws.command(self.grasp_force + self.trim)


class NaiveJawGrasp(Controller):
    """The naive grasp of thesis 3.4.1 on a gripper: once the arm has stopped (`contact`),
    close until the jaw motor meets the object, then press with `grasp_force` (the robust
    grasp's), or `squeeze` of its effort limit without one. No tactile sensing, no
    re-centring, no force check: the baseline."""

    def __init__(self, ctx: Context) -> None:
        super().__init__(ctx)
        self.jaws = Jaws(ctx, "motor")
        force = self.params.get("grasp_force")
        if force is None:
            force = float(self.params["squeeze"]) * float(ctx.info.hand.effort_limit[0])
        self.force = float(force)
        self.speed = NAIVE_SPEED * float(ctx.info.hand.velocity_limit[0])

    def start(self, readings: Readings) -> None:
        self.reference = float(readings.hand_q[0])
        self.ctx.memory[EMPTY_HAND] = world_load(readings)  # a grasp begins empty-handed

    def update(self, readings: Readings, dt: float) -> ControlData:
        if self.status is Status.DONE:
            return self.jaws.command(self.force)
        if self.status is Status.RUNNING and self.ctx.blackboard.contact:
            # Held back too: the Melfa's arm stopping on the box shook its open jaws' servo
            # past the touch force, and the grasp said it had closed with the jaws wide open.
            if self.jaws.both_touch(readings, self.force) and self.jaws.held(readings, self.reference):
                self.finish(Status.DONE, "closed on the object")
                return self.jaws.command(self.force)
            if self.jaws.empty(readings):
                self.finish(Status.ERROR, "the jaws closed on nothing")
            else:
                self.reference += self.jaws.closing * self.speed * dt
        return position_command(np.array([self.reference]))
