"""The slide primitive (thesis 3.3.5, Eq. 3.6) as a phase machine: the arm presses on the
object's top with a normal force between LOWER_ and UPPER_FORCE_THRESHOLD along
SURFACE_NORMAL n and drags it to the target, the hand held in its (hook) preshape.

It says success only when its own sensors say it carried the object to its target: the
contact was found where the object's top should be (the lowest of the hand's pads over the
object, from its own kinematics, at the top the task believes the object has), held all the
way, the hand went to within `tolerance` of the target, and over all the way but SLIP_LIMIT
the wrist felt the drag of the object sliding on the surface rather than that of the hand's
surfaces slipping over it (belief only: the object's believed friction and weight, the
hand's surface friction from its description, never the simulator's). Where the robot has a
range sensor along its approach axis, it also finds the object's edges before pressing
(`primitives.arm.slide_edges`: an object standing off its believed pose is pressed where the
task meant and taken to its own target) and sees its trailing edge within SLIP_LIMIT of where
the target puts it after the drag. Anything else is an error, with why.
The wrench is read as in `primitives.arm.surface`: the contact force on the hand, tared in
free air, pressing makes it point along +n.
"""

from __future__ import annotations

from enum import Enum

import numpy as np

from atd.model.vocabulary import ObjectClass
from primitives.arm.motion import GAIN, clamp_norm, norm, orientation_twist, unit
from primitives.arm.move import arm_output
from primitives.arm.slide_edges import INSET, Sweep, moved, shift, sweeps
from primitives.base import Context, ControlData, Controller, Status
from primitives.filters import ContactWrench, LowPass
from primitives.robot import Readings

# m the hand rises before taring: more than a pad's compression, so whatever the state
# started touching (a guarded move ends on contact) no longer loads the wrist.
CLEARANCE = 0.005
# s the hand holds still in free air before taring: the wrist settles from the rise.
TARE_TIME = 0.3
# m/s of normal motion per N of force error. Small enough that a stiff contact
# (2e5 N/m measured on the Melfa against the table) stays stable at 200 Hz: 5e-4 * 2e5 * 0.005 = 0.5.
FORCE_GAIN = 5e-4
# m the hand's lowest pad may be below the object's believed top when it first presses, or
# sink below where it first pressed while dragging: further, it presses on whatever is below
# (fingers straddling a box small for the preshape, a box that is not there; ours).
SLIDE_DEPTH = 0.01
# s the force must stay in the band before the drag starts: pressing is established.
SETTLE_TIME = 0.2
# Fraction of LOWER_FORCE_THRESHOLD under which the contact counts as gone while dragging.
LOST_FRACTION = 0.3
# s the contact may be gone while dragging (a stick-slip dip) before the object counts as lost.
LOST_TIME = 0.3
# N of tangential force against the motion below which nothing is dragged (a hand in air, ~0).
DRAG_FORCE = 0.5
# m/s^2: the object's weight from its believed mass.
GRAVITY = 9.81
# The object's friction where the task does not say: the simulators' default for its contacts.
DEFAULT_FRICTION = 1.0
# s time constant of the low-pass on the felt drag: smooths stick-slip.
DRAG_FILTER = 0.1
# m the object may lag the hand over the drag, felt or seen, and the slide still say it carried it (docs/slide.md)
SLIP_LIMIT = 0.01
# N of pressing under which the hand has let go of the object, rising after the drag.
LET_GO_FORCE = 1.0
# m the hand rises over where CLEAR took it while the beam looks for edges: clear of the object's top
SWEEP_RISE = 0.015
# m/s the hand moves between sweeps; and sweeps, at 200 Hz ticks a 0.15 mm step of the edge.
MOVE_SPEED = 0.08
SWEEP_SPEED = 0.03
# m from a point the hand moves to where it counts as there.
ARRIVED = 0.001
# cos: approach axis within 10° of -n, or the beam misses the top at its edges (the task's pose is then trusted)
BEAM_ALIGNMENT = 0.985


class Phase(Enum):
    """Where the slide is; the value is the method that runs a tick of it."""

    CLEAR = "_clear"  # rising CLEARANCE off whatever the state began touching
    TO_SWEEP = "_to_sweep"  # above the object's top, to where the next sweep starts (a range sensor only)
    SWEEP = "_sweep"  # the range sensor's beam moved outward until it drops off the object's edge
    # after the trailing and side edges' sweeps: BACK; after the trailing edge's at the target: done or error
    BACK = "_back"  # back to where CLEAR rose to, the object located
    TARE = "_tare"  # still in free air: the wrist's empty reading is taken
    DESCEND = "_descend"  # down along -n at CONTACT_VELOCITY until the object's top is felt
    PRESS = "_press"  # Eq. 3.6's normal law only, until the force is in the band
    DRAG = "_drag"  # Eq. 3.6: in the band, towards the target at TARGET_VELOCITY, until within `tolerance`
    RELEASE = "_release"  # at the target: rise until the object no longer loads the hand, then the check's sweep


class Slide(Controller):
    """Press on the object with a normal force between the two thresholds while moving it
    to the target (Eq. 3.6): too little force, move towards the surface at CONTACT_VELOCITY;
    too much, move away; in between, move along the surface at TARGET_VELOCITY.

    Along the normal the speed is proportional to the force's distance from the band's
    middle, up to CONTACT_VELOCITY, rather than the equation's bang-bang: against a stiff
    contact 5 mm/s for one tick already jumps across the band, and the force would chatter
    from one side to the other without ever letting the tangential motion start.
    """

    def __init__(self, ctx: Context) -> None:
        super().__init__(ctx)
        p = self.params
        self.target = np.asarray(p["target"], float)
        self.normal = unit(p["surface_normal"])
        self.expected_top = self._believed_top()
        obj = ctx.object
        self.friction = obj.friction if obj is not None and obj.friction is not None else DEFAULT_FRICTION
        self.weight = GRAVITY * (obj.weight or 0.0) if obj is not None else 0.0
        self.lower = float(p["lower_force_threshold"])
        self.upper = float(p["upper_force_threshold"])
        self.target_velocity = float(p["target_velocity"])
        self.contact_velocity = float(p["contact_velocity"])
        self.tolerance = float(p["tolerance"])
        self.contact = ContactWrench(float(p["filter_time"]))
        self.drag = LowPass(DRAG_FILTER)

    def start(self, readings: Readings) -> None:
        self.rotation = readings.tcp[:3, :3].copy()
        self.phase = Phase.CLEAR
        self.hold = readings.tcp[:3, 3] + CLEARANCE * self.normal  # where the hand goes or stays
        self.meant = self.hold.copy()  # where the task meant the hand to press, risen CLEARANCE
        self.clock = 0.0  # s in the current phase's condition (tare, settle, contact gone)
        self.top = 0.0  # height along n where the object's top was felt
        self.pressing = 0.0
        self.dragged = 0.0  # m of the drag's path with the drag felt
        self.travelled = 0.0  # m of the drag's path
        self.drag.reset(np.zeros(1))
        # the edges to look for, where the robot has a range sensor along its approach axis and
        # the task says where the object stands; elsewhere the slide trusts the task's pose
        way = self._tangential(self.target - readings.tcp[:3, 3])
        looks_down = float(readings.tcp[:3, 2] @ -self.normal) > BEAM_ALIGNMENT
        self.sweeps: list[Sweep] = (list(sweeps(self.ctx.object, self.normal, unit(way)))
                                    if self._sweeps_object() and looks_down and norm(way) > self.tolerance else [])
        self.locating = len(self.sweeps)  # the sweeps before the drag; the one after it checks
        self.edges: list[float] = []  # m from each sweep's centre along it, as seen
        self.shift = np.zeros(3)  # m the object stands from its believed pose, from its edges
        self.floor = np.inf  # m the range read over the object's top as a sweep began

    def update(self, readings: Readings, dt: float) -> ControlData:
        if self.status is not Status.RUNNING:
            return arm_output(np.zeros(6))
        position = readings.tcp[:3, 3]
        force = readings.tcp[:3, :3] @ self.contact.update(readings, dt)[:3]
        self.pressing = float(force @ self.normal)
        v = getattr(self, self.phase.value)(readings, position, force, dt)
        if self.status is not Status.RUNNING:
            return arm_output(np.zeros(6))
        w, _ = orientation_twist(self.rotation, readings.tcp[:3, :3])
        return arm_output(np.concatenate([v, w]))

    def _sweeps_object(self) -> bool:
        obj = self.ctx.object
        return self.ctx.info.has_range and obj is not None and obj.pose is not None

    def _believed_top(self) -> float:
        """Height along n of the object's top as the task believes it; without an object
        pose, the target's height is taken for where the hand's lowest pad presses."""
        obj = self.ctx.object
        if obj is None or obj.pose is None:
            return float(self.target @ self.normal)
        return float(np.asarray(obj.pose.position, float) @ self.normal) + obj.half_height

    def _height(self, position: np.ndarray) -> float:
        return float(position @ self.normal)

    def _lowest(self, readings: Readings) -> float:
        """Height along n of the lowest of the hand's pads over the object's believed
        footprint (all of them where none is), from the hand's own forward kinematics: a
        hook's fingers hanging behind the object's trailing face are not pressing on it."""
        pads = self.ctx.info.hand.pad_surfaces(readings.hand_q)[:, :3, 3]
        world = readings.tcp[:3, 3] + pads @ readings.tcp[:3, :3].T
        over = world[self._over_object(world)]
        return float(np.min((over if len(over) else world) @ self.normal))

    def _over_object(self, points: np.ndarray) -> np.ndarray:
        """Which of `points` lie over the object's footprint as the task believes it."""
        obj = self.ctx.object
        if obj is None or obj.pose is None:
            return np.ones(len(points), bool)
        pose = obj.pose.as_array()
        local = (points - pose[:3, 3] - self.shift) @ pose[:3, :3]
        size = obj.effective_size
        if (obj.object_class or ObjectClass.BOX) is ObjectClass.BOX:
            return np.all(np.abs(local[:, :2]) <= np.array(size[:2]) / 2, axis=1)
        return np.hypot(local[:, 0], local[:, 1]) <= size[0]

    def _tangential(self, offset: np.ndarray) -> np.ndarray:
        return offset - float(offset @ self.normal) * self.normal

    def _clear(self, readings: Readings, position: np.ndarray, force: np.ndarray, dt: float) -> np.ndarray:
        to_go = self.hold - position
        if float(to_go @ self.normal) <= ARRIVED:
            self.phase, self.clock = (Phase.TO_SWEEP if self.sweeps else Phase.TARE), 0.0
        return self.contact_velocity * self.normal + GAIN * self._tangential(to_go)

    def _sweep_height(self) -> float:
        """Height along n of the TCP while the range sensor looks for the object's edges."""
        return self._height(self.hold) + SWEEP_RISE

    def _to(self, goal: np.ndarray, position: np.ndarray, speed: float) -> tuple[np.ndarray, bool]:
        """The velocity towards `goal`, and whether the hand is there."""
        return clamp_norm(GAIN * (goal - position), speed), norm(goal - position) < ARRIVED

    def _to_sweep(self, readings: Readings, position: np.ndarray, force: np.ndarray, dt: float) -> np.ndarray:
        sweep = self.sweeps[len(self.edges)]
        goal = self._tangential(sweep.start) + self._sweep_height() * self.normal
        v, there = self._to(goal, position, MOVE_SPEED)
        if there:
            self.phase, self.floor = Phase.SWEEP, np.inf
        return v

    def _sweep(self, readings: Readings, position: np.ndarray, force: np.ndarray, dt: float) -> np.ndarray:
        """Outward until the beam reads the object's half height further than over its top
        (or nothing): the edge, where the beam is now."""
        sweep = self.sweeps[len(self.edges)]
        seen = np.inf if readings.range is None else float(readings.range)
        self.floor = min(self.floor, seen)
        gone = float(self._tangential(position - sweep.start) @ sweep.outward)
        if seen > self.floor + self.ctx.object.half_height:
            self._found(float((position - sweep.centre) @ sweep.outward))
        elif gone > 2 * INSET:
            what, where = (("found no edge of the object", "the task says") if len(self.edges) < self.locating
                           else ("the object is not at its target", "the target puts"))
            self.finish(Status.ERROR, f"{what}: the range sensor read no drop off its top within "
                                      f"{INSET * 100:.0f} cm either side of where {where} its edge "
                                      f"(read {self.floor:.3f} m at the least)")
        height = self._sweep_height() - self._height(position)
        return SWEEP_SPEED * sweep.outward + GAIN * height * self.normal

    def _found(self, seen: float) -> None:
        """An edge seen `seen` m from its sweep's centre: the next sweep; after the locating
        ones, back to press where the object stands; after the check, the verdict."""
        self.edges.append(seen)
        if len(self.edges) < self.locating:
            self.phase = Phase.TO_SWEEP
        elif len(self.edges) == self.locating:
            self.shift, self.phase = shift(self.sweeps, self.edges), Phase.BACK
        else:
            self._verdict(seen - self.sweeps[-1].edge)

    def _back(self, readings: Readings, position: np.ndarray, force: np.ndarray, dt: float) -> np.ndarray:
        """To where CLEAR rose to, moved as far as the object stands from its believed pose:
        the hand presses where the task meant on the object, and the same target takes the
        object to its own."""
        goal = self.hold + self.shift
        v, there = self._to(goal, position, MOVE_SPEED)
        if there:
            self.hold, self.phase, self.clock = goal, Phase.TARE, 0.0
        return v

    def _tare(self, readings: Readings, position: np.ndarray, force: np.ndarray, dt: float) -> np.ndarray:
        self.clock += dt
        if self.clock >= TARE_TIME:
            self.contact.start(readings)
            self.phase = Phase.DESCEND
        return GAIN * (self.hold - position)

    def _descend(self, readings: Readings, position: np.ndarray, force: np.ndarray, dt: float) -> np.ndarray:
        sunk = self.expected_top - self._lowest(readings)
        if sunk > SLIDE_DEPTH:
            felt = "pressing on something below it" if self.pressing >= self.lower else "without feeling anything"
            self.finish(Status.ERROR, f"nothing to press on: the hand's lowest pad sank {sunk * 100:.1f} cm below "
                                      f"the object's top, {felt} ({self.pressing:.1f} N)")
        elif self.pressing >= self.lower:
            self.phase, self.clock, self.top = Phase.PRESS, 0.0, self._height(position)
        return -self.contact_velocity * self.normal + GAIN * self._tangential(self.hold - position)

    def _normal_law(self) -> np.ndarray:
        speed = FORCE_GAIN * (self.pressing - (self.upper + self.lower) / 2)
        return max(-self.contact_velocity, min(self.contact_velocity, speed)) * self.normal

    def _press(self, readings: Readings, position: np.ndarray, force: np.ndarray, dt: float) -> np.ndarray:
        in_band = self.lower < self.pressing < self.upper
        self.clock = self.clock + dt if in_band else 0.0
        if self.clock >= SETTLE_TIME:
            self.phase, self.clock = Phase.DRAG, 0.0
            self.hold = position.copy()
        return self._normal_law() + GAIN * self._tangential(self.hold - position)

    def _drag(self, readings: Readings, position: np.ndarray, force: np.ndarray, dt: float) -> np.ndarray:
        along = self._tangential(self.target - position)
        left = float(np.linalg.norm(along))
        sunk = self.top - self._height(position)
        self.clock = self.clock + dt if self.pressing < LOST_FRACTION * self.lower else 0.0
        if sunk > SLIDE_DEPTH:
            self.finish(Status.ERROR, f"lost the object: the hand sank {sunk * 100:.1f} cm below the top it "
                                      f"pressed on, {left * 100:.1f} cm from the target")
        elif self.clock > LOST_TIME:
            self.finish(Status.ERROR, f"lost the object: the contact went ({self.pressing:.1f} N) "
                                      f"{left * 100:.1f} cm from the target")
        if self.status is not Status.RUNNING:
            return np.zeros(3)
        if left < self.tolerance:
            return self._arrive(left)
        direction = along / left
        felt = float(self.drag(np.array([-float(force @ direction)]), dt)[0])
        step = float(np.linalg.norm(self._tangential(position - self.hold)))
        self.hold = position.copy()
        self.travelled += step
        self.dragged += step if self._carries(felt) else 0.0
        v = self._normal_law()
        if self.lower < self.pressing < self.upper:
            v = v + clamp_norm(GAIN * along, self.target_velocity)
        return v

    def _carries(self, felt: float) -> bool:
        """Whether `felt` N of drag says the object slides with the hand: nearer the friction
        of the object on the surface under it, mu (F_n + m g), than that of the hand's
        surfaces slipping over its top, k mu F_n (k: how much better they grip); where the
        two are alike (an object of no known weight), nothing tells them apart."""
        pressing = max(self.pressing, 0.0)
        carried = self.friction * (pressing + self.weight)
        slipping = self.ctx.info.hand.surface_friction * self.friction * pressing
        return felt >= DRAG_FORCE and abs(felt - carried) < abs(felt - slipping)

    def _arrive(self, left: float) -> np.ndarray:
        """At the target: the object is as far short of its own as the hand slipped over it
        (no carried drag felt), which must be within SLIP_LIMIT."""
        slipped = self.travelled - self.dragged
        if slipped > SLIP_LIMIT:
            what = "moved nothing" if self.dragged < SLIP_LIMIT else "left the object behind"
            self.finish(Status.ERROR, f"{what}: no carried drag over {slipped * 100:.1f} cm of the "
                                      f"{self.travelled * 100:.1f} cm slid (> {SLIP_LIMIT * 100:.1f} cm), the hand "
                                      f"slipped over the object: no more drag than its own friction on it")
            return np.zeros(3)
        self.phase, self.slipped = Phase.RELEASE, slipped
        return np.zeros(3)

    def _release(self, readings: Readings, position: np.ndarray, force: np.ndarray, dt: float) -> np.ndarray:
        if self.pressing < LET_GO_FORCE and self._height(position) > self.top + CLEARANCE:
            if self.locating:  # the trailing edge's sweep where the target puts the object
                self.sweeps.append(moved(self.sweeps[0], self._tangential(self.target - self.meant)))
                self.phase = Phase.TO_SWEEP
            else:
                self.finish(Status.DONE, self._carried())
        return self.contact_velocity * self.normal + GAIN * self._tangential(self.hold - position)

    def _carried(self) -> str:
        return (f"slid the object to the target: pressed all the way, carried drag felt over all but "
                f"{self.slipped * 1000:.1f} mm of {self.travelled * 100:.1f} cm")

    def _verdict(self, behind: float) -> None:
        """The object's trailing edge seen `behind` m further back than the target puts it."""
        if abs(behind) > SLIP_LIMIT:
            what = "left the object behind" if behind > 0 else "pushed the object past its target"
            self.finish(Status.ERROR, f"{what}: its trailing edge seen {abs(behind) * 100:.1f} cm "
                                      f"{'short of' if behind > 0 else 'past'} where the target puts it "
                                      f"(> {SLIP_LIMIT * 100:.1f} cm)")
        else:
            self.finish(Status.DONE, f"{self._carried()}, found {np.linalg.norm(self.shift) * 100:.1f} cm from where "
                                     f"the task says and seen {behind * 1000:+.1f} mm from its target")
