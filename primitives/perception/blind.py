"""Blind exploration (thesis 3.4.3, Fig. 3.26a): find an object in the container by touch.

A plan of `explore` moves. The hand comes over a point of the container's floor drawn at
random, clear of its rim, and goes down until it feels something (wholly over the rim, where
no object lay, at a free move's speed; in the container at an explore's). A contact above the
floor (the floor's height is the container's believed pose; the contact's, the TCP's height
less the hand's reach) is an object's top: the approach is there. The floor itself starts a
sweep: the hand, its lowest point just above the floor, goes along the container in lanes (a
boustrophedon) until it feels something, which is an object ahead of it. The lanes keep the
whole hand off the walls, so the sweep then goes round them with the hand's tip alone in
the band they leave, as low as its wider part, over the rim, lets it; where that is over a
lying spray can, along each wall at the lanes' height instead, the hand turned its narrower
side towards it; a sweep that feels nothing found nothing. A sweep's contact places the
object only by its near side, at the height of the hand's tip, so the hand then feels for
its top: it backs off, rises just over the rim, comes over the object's near part and goes
down onto it (landing on the floor, the approach keeps the sweep's estimate, its top unknown).
On a top, found either way, the hand comes down beside it along the container's axes to feel
how far it reaches, and the approach is moved towards where it goes on and turned so the jaws
close across a top long along the box's y; where the walls keep the hand from coming down
beside a top, its tip alone feels there, as near the wall as it fits, wherever the hand's
wider part stays over the rim; a top that goes on towards a wall and not the other way lies
against it, and the approach is moved up to SIDE_STEP towards it: a grasp of the open hand is
kept off the wall by its own reach anyway, and what presses on the top to free it
(examples/free_one.xml) presses on its middle, not on its edge towards the box's middle; the
approach says the top's height (`Approach.top`), so the grasp knows a jaw landing there for a
jaw on the object rather than close above it. A hand whose lowest points are fingertips spread
apart (`spread_tip`: the SDH2's stretched fingers) lands on a top under one of them, not under its
TCP: it comes down beside with its tip's edge over where it landed instead, and the approach goes
the tip's reach towards the side the top is likelier under. A look after another starts where that one's
approach lay: landing on an object there, the grasp took nothing out, and the jaws are turned
another way this time (`TURNS`). Once every turn has been tried there, the look comes down at
random a hand's reach away from it instead: an object no turn of the jaws takes (against
another, or a wall) would hold every later round. """

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from enum import Enum

import numpy as np

from atd.model.controllers import ARM_CONTROLLERS
from atd.model.frames import axis_rotation
from primitives.arm.approach_phases import SETTLE
from primitives.arm.explore import ARRIVED, Explore
from primitives.arm.turn import Turn
from primitives.arm.walls import FREE_SPEED, RIM_CLEARANCE
from primitives.base import Context, ControlData, Status
from primitives.perception.container import approach_pose
from primitives.perception.generators import roomier_half, walls_push
from primitives.perception.perceiver import Perceiver
from primitives.robot import Readings
from primitives.values import Approach, Contact

PROBE_BEYOND = 0.02  # m below the believed floor the probe goes before it gives up: the floor is not there
# m past an object's near side, along the sweep, where the hand comes down to feel its top: the
# library's objects are 3.8-7.5 cm across whichever way they lie, so their middle lies 1.9-3.8 cm
# past it (ours)
FEEL_INTO = 0.025
BACK_OFF = 0.01  # m the hand backs off what a sweep met before it rises: its fingers rubbing the side read as a contact
# m the hand rises off what it came down on before it says so: stopped on a contact it still
# presses (the Melfa's wrist read 13 N on the floor 0.1 s after a 4 cm/s descent stopped), and
# the next state, tared on that, read its going as a contact
LIFT_OFF = 0.01
# m out from where the hand landed on an object's top, along each of the container's axes, that
# it feels whether the top goes on (the hand's tip comes down with its nearer edge there): jaws
# opening 6.8 cm (the Melfa's) close round what ends within 3.4 cm of their middle, so a top
# reaching 3 cm out both ways is better closed across; the library's objects are 3.8-5.2 cm
# across their narrow side and 6.5-8.5 cm along their long one (ours)
SIDE_STEP = 0.03
SIDE_RISE = 0.01  # m over the top found that the hand moves from one side to the next
# m below the top found that the hand comes down at a side before it takes the top not to go
# on there: a lying cylinder's top curves away, and what lies below is the floor or another object
SIDE_DEPTH = 0.015
# m more than the hand's reach that the sweep keeps from the walls: at exactly its reach the
# Melfa's gripper body, below the rim, rubbed the wall along a lane and read 9.9 N
WALL_CLEARANCE = 0.005
# m the hand's tip keeps from the walls going round them after the lanes: with 5 and 10 mm the
# Baxter, its paddles 9 mm or more off the +y wall by the truth, read a contact in an empty box
# and the look found an object there (docs/empty-the-box.md); the library's objects, 3.8 cm or
# more across, still reach under a tip 1.5 cm off the wall
WALLS_CLEARANCE = 0.015
# m: the library's lowest object lying, the spray can on its side: a ring round the walls whose
# lowest point is not under it passes over it, so the sweep goes along the walls at the lanes'
# height instead where the hand fits there (the Barrett's ring: 4.3 cm up)
LOWEST_TOP = 0.038
VERTICAL = np.array([0.0, 0.0, 1.0])  # the world's z, about which the hand turns between legs
# rad the jaws turn from what the feel chose, the 1st, 2nd, 3rd, ... time in a row the probe,
# come down where the last approach lay, lands on an object there: a quarter turn first (the
# feel chose the wrong one of the box's axes), then the diagonals (a wood block or a spray can
# lying 32-45 degrees off the box's axes is longer than the Melfa's jaws open along either)
TURNS = (0.0, math.pi / 2, math.pi / 4, -math.pi / 4)
_FREE_MOVE = ARM_CONTROLLERS["cartesian_move"].params  # a free move's contact force, from its own spec
# N over the start's that stops a transit, where any contact is an error anyway: at the explore's
# 3 N a look begun as a rise out of the box stopped read its jolt as a contact
TRANSIT_FORCE = float(_FREE_MOVE["force_threshold"].default)
# N over the start's that stops the rise out of where the last state left the hand, which may have
# ended pressing on something (pick_one.xml's clear stopped on 15 N, and rising off it read that as a
# contact at TRANSIT_FORCE): only what holds it down, as pick_one.xml's rise
RISE_FORCE = 150.0
DRAWS = 32  # random probe points drawn for one a hand's reach from a spot given up (else the farthest is taken)
TRIED = "blind_exploration_tried"  # in Context.memory: the last approach given (`Tried`)


class Leg(Enum):
    """What an explore move is for, and so what a contact on the way means."""

    RISE = "rise"  # up out of where the last state left the hand: something holding it down, an error
    TRANSIT = "transit"  # over the container to the probe: something in the way, an error
    PROBE = "probe"  # down onto the floor: an object's top, or the floor
    SWEEP = "sweep"  # along the floor: an object ahead
    WALLS = "walls"  # round the walls, the hand's tip alone in the band the lanes leave: an object ahead
    TURN = "turn"  # the hand turned where it stands, over the rim: nothing to meet
    DOWN = "down"  # down beside a wall to the lanes' height: an object's top
    RETREAT = "retreat"  # back, up and over what a sweep met: the sweep's estimate is the approach
    FEEL = "feel"  # down onto what a sweep met: its top, or the floor beside it
    LIFT = "lift"  # off what the hand came down on
    ABOVE = "above"  # over the top found, from side to side: a contact ends the feeling
    SIDE = "side"  # down beside the top found: whether it reaches there


@dataclass(frozen=True)
class Waypoint:
    """Where the next explore move goes (the TCP's, world), and what it is for."""

    to: np.ndarray  # (3,)
    kind: Leg
    side: tuple[int, int] = (0, 0)  # a SIDE's: the container's axis (0 x, 1 y) and which way (+1, -1)
    turn: float = 0.0  # a TURN's: rad about the vertical from how the hand was turned when the look began


@dataclass(frozen=True)
class Swept:
    """What a sweep met: its contact, and where the hand comes down to feel the object's top
    (world, at the sweep's height: the approach if the feel finds nothing higher)."""

    contact: Contact
    estimate: np.ndarray  # (3,)
    by_walls: bool = False  # met going round the walls: the hand comes down there no lower than it went round


@dataclass
class Finding:
    """What the hand has felt of an object: a point on it (world: on its top where `on_top`, or
    at the sweep's height where the sweep alone placed it), how it was felt, and whether its
    top reaches SIDE_STEP out each way the hand came down beside it: (the container's axis, +1
    or -1) -> reaches."""

    point: np.ndarray  # (3,)
    how: str
    on_top: bool
    reaches: dict[tuple[int, int], bool] = field(default_factory=dict)
    by_wall: set[tuple[int, int]] = field(default_factory=set)  # sides felt by the tip alone, nearer a wall
    tip: np.ndarray = field(default_factory=lambda: np.zeros(2))  # its reach along the container's x y (`_sides`)


@dataclass(frozen=True)
class Tried:
    """The last approach this run's blind exploration gave: over `point` (world), with the
    jaws turned by TURNS[times % len(TURNS)] from what the feel chose, `times` being how many
    looks in a row before it had landed on an object where the approach before lay."""

    point: np.ndarray  # (3,)
    times: int


class BlindExploration(Perceiver):
    """The blind exploration generator as a controller: each explore move tared afresh from a
    hand held still for SETTLE after the one before, as the robust grasp does after its moves
    (stopping jolts the wrist by a few newtons)."""

    method = "blind_exploration"

    def __init__(self, ctx: Context) -> None:
        super().__init__(ctx)
        p = self.params
        self.margin = float(p["hand_radius"])
        self.room = self.margin + WALL_CLEARANCE  # the sweep's, from the walls
        self.sweep_height = float(p["sweep_height"])
        self.lane_spacing = float(p["lane_spacing"])
        self.floor_band = float(p["floor_band"])
        self.tip = np.array(p["sweep_extent"], float)
        self.tip_length = float(p["tip_length"])
        self.spread = bool(p["spread_tip"])
        # the grasp's footprint (`grasp_footprint`: the SDH2's thumb 8.9 cm out, its fingers 5.0 cm the
        # other way), where its pinch closes along the hand's y as the approach's yaw takes it to
        footprint = tuple(float(v) for v in p["grasp_footprint"])
        self.footprint = footprint if float(p["grasp_turn"]) == 0.0 else (0.0, 0.0, 0.0, 0.0)
        self.extent = np.array(p["hand_extent"], float)
        # m over the floor the hand's lowest point goes round the walls (`_along_walls`); None
        # where `tip_length` is not known (the hand may be as wide all the way down: the lanes
        # went round as near the walls as it fits)
        self.walls_height = None if self.tip_length <= 0.0 else max(
            self.sweep_height, self.container.rim + WALL_CLEARANCE - self.tip_length - self.container.floor)
        inner = self.container.inner
        if np.any(inner[:2] <= 2 * self.margin):
            raise ValueError(f"a hand reaching {self.margin:g} m sideways cannot sweep a container "
                             f"{inner[0]:g} x {inner[1]:g} m inside without touching its walls")
        self.moving = {"speed": p["speed"], "force_threshold": p["force_threshold"], "filter_time": p["filter_time"]}

    def start(self, readings: Readings) -> None:
        super().start(readings)
        here = readings.tcp[:3, 3]
        self.level = readings.tcp[:3, :3].copy()  # how the hand is turned: TURNs turn it from there
        clear = self._clear()
        low, high = self.container.footprint(self.room)
        self.tried: Tried | None = self.ctx.memory.get(TRIED)
        given_up = self.tried is not None and self.tried.times >= len(TURNS) - 1
        self.again = False  # the probe landed on an object where the last approach lay
        self.walled: set[int] = set()  # the container's axes whose walls the sweep went along at the lanes' height
        if given_up:  # every turn of the jaws tried there: come down elsewhere, as a first look does
            xy = self._away(self.container.to_local(self.tried.point[None])[0][:2], low, high)
            self.tried = None
        elif self.tried is None:
            xy = self.ctx.rng.uniform(low, high)
        else:  # down where the last approach lay: what it did not take out is likely still there
            xy = np.clip(self.container.to_local(self.tried.point[None])[0][:2], low, high)
        probe = self.container.to_world(np.array([[*xy, 0.0]]))[0]
        over = self._over_rim()
        # up to just over the rim first, if lower; then straight over the probe, clear of the rim, and
        # fast down to just over it (a contact there is a top over the rim), then down until a contact
        self.plan = [Waypoint(np.array([here[0], here[1], max(float(here[2]), over)]), Leg.RISE),
                     Waypoint(np.array([probe[0], probe[1], clear]), Leg.TRANSIT),
                     Waypoint(np.array([probe[0], probe[1], over]), Leg.PROBE),
                     Waypoint(np.array([probe[0], probe[1], self._below_floor()]), Leg.PROBE)]
        self.explore: Explore | None = None
        self.swept: Swept | None = None
        self.result: Finding | None = None  # once the hand has felt an object
        self._next(readings)

    def _away(self, spot: np.ndarray, low: np.ndarray, high: np.ndarray) -> np.ndarray:
        """A random point of the floor (the container's frame) at least the hand's reach
        sideways from `spot`, where one of DRAWS draws is, else the farthest of them."""
        draws = self.ctx.rng.uniform(low, high, size=(DRAWS, 2))
        distance = np.linalg.norm(draws - spot, axis=1)
        far = np.flatnonzero(distance >= self.margin)
        return draws[far[0]] if far.size else draws[int(np.argmax(distance))]

    def _clear(self) -> float:
        """The TCP's height with the hand's lowest point the approach's height over the container's rim."""
        return self.container.rim + self.approaching.height + self.approaching.reach

    def _over_rim(self) -> float:
        """The TCP's height with the hand's lowest point RIM_CLEARANCE over the container's rim."""
        return self.container.rim + RIM_CLEARANCE + self.approaching.reach

    def _below_floor(self) -> float:
        """The TCP's height with the hand PROBE_BEYOND below the believed floor: where a descent gives up."""
        return self.container.floor + self.approaching.reach - PROBE_BEYOND

    def update(self, readings: Readings, dt: float) -> ControlData:
        if self.explore is None:
            return super().update(readings, dt)
        out = self.explore.update(readings, dt)  # a finished move holds where it ended
        if self.status is Status.RUNNING and self.explore.status is not Status.RUNNING:
            if not self.handled:
                self.handled, self.still = True, 0.0
                self._ended(readings)
            else:
                self.still += dt
                if self.still >= SETTLE:
                    self._next(readings)
        return out

    def _next(self, readings: Readings) -> None:
        """Start the explore move to the plan's next waypoint (one already reached is passed
        over); with none left, the sweep is over and found nothing."""
        here = readings.tcp[:3, 3]
        while self.plan and self.plan[0].kind is not Leg.TURN and np.linalg.norm(self.plan[0].to - here) < ARRIVED:
            self.plan.pop(0)
        if not self.plan:
            if self.result is not None:
                self._conclude()
            else:
                low = "".join(f" and along its {'xy'[axis]} walls {self.sweep_height * 100:g} cm"
                              for axis in sorted(self.walled))
                ring = self.walls_height is not None and len(self.walled) < 2
                walls = low + (f" and along its walls {self.walls_height * 100:.3g} cm" if ring else "")
                self.found(None, f"swept the container's floor {self.sweep_height * 100:g} cm above it{walls} "
                                 f"without a contact")
            return
        self.leg = self.plan.pop(0)
        if self.leg.kind is Leg.TURN:
            self.explore = Turn(self.ctx, _turned(self.level, self.leg.turn))
            self.explore.start(readings)
            self.handled = False
            return
        way = self.leg.to - here
        distance = float(np.linalg.norm(way))
        moving = dict(self.moving)
        if min(float(here[2]), float(self.leg.to[2])) >= self._over_rim() - ARRIVED:  # wholly over the rim
            moving["speed"] = max(float(moving["speed"]), FREE_SPEED)
        least = {Leg.RISE: RISE_FORCE, Leg.TRANSIT: TRANSIT_FORCE}.get(self.leg.kind, 0.0)
        moving["force_threshold"] = max(float(moving["force_threshold"]), least)
        self.explore = Explore(replace(self.ctx, params={**moving, "direction": tuple(way / distance),
                                                         "max_distance": distance}))
        self.explore.start(readings)
        self.handled = False

    def _ended(self, readings: Readings) -> None:
        """What the explore move just ended tells: go on, found, or give up."""
        contact, kind = self.explore.found, self.leg.kind
        if self.explore.blocked:
            self.finish(Status.ERROR, f"a move of the exploration stopped short: {self.explore.reason}")
        elif kind is Leg.ABOVE and contact is not None:
            self.plan = []  # something higher than the top found: what is known so far will do
        elif kind is Leg.SIDE:
            self.result.reaches[self.leg.side] = contact is not None
        elif kind in (Leg.RISE, Leg.TRANSIT) and contact is not None:
            x, y, z = contact.point
            self.finish(Status.ERROR, f"something in the way over the container: a contact at ({x:.3f}, {y:.3f}, "
                                      f"{z:.3f}) on the way to the probe")
        elif kind in (Leg.PROBE, Leg.FEEL) and contact is None and self.plan:
            pass  # down to just over the rim: the descent goes on
        elif kind is Leg.FEEL and contact is None and self.swept.by_walls:
            self._estimated(readings, "the descent beside the wall met nothing as low as the hand fits there")
        elif kind in (Leg.PROBE, Leg.FEEL) and contact is None:
            self.finish(Status.ERROR, f"no floor within {PROBE_BEYOND * 100:g} cm below where the container's "
                                      f"floor is believed to be ({self.container.floor:.3f} m)")
        elif kind is Leg.DOWN and contact is not None:
            top = self._top(contact)
            if top is not None:
                self._approach(readings, np.array([*contact.point[:2], top]),
                               f"the descent beside a wall felt it: {self._felt(contact)}", True)
        elif kind is Leg.PROBE:
            top = self._top(contact)
            if top is not None:
                self.again = self.tried is not None
                self._approach(readings, np.array([*contact.point[:2], top]),
                               f"the probe felt it: {self._felt(contact)}", True)
            else:
                self.plan = self._sweep(readings)
        elif kind in (Leg.SWEEP, Leg.WALLS) and contact is not None:
            self.swept = Swept(contact, self._ahead(readings, contact, kind is Leg.WALLS), kind is Leg.WALLS)
            self.plan = self._feel(readings, self.swept)
        elif kind is Leg.RETREAT and contact is not None:
            self._estimated(readings, f"a contact on the way back and over it ({self._felt(contact)})")
        elif kind is Leg.FEEL:
            top = self._top(contact)
            if top is None:
                self._estimated(readings, "the descent beside it met the floor")
            else:
                self._approach(readings, np.array([*contact.point[:2], top]),
                               f"the sweep felt it ({self._felt(self.swept.contact)}), the descent onto it its top "
                               f"({self._felt(contact)})", True)

    def _top(self, contact: Contact) -> float | None:
        """The height of the hand's lowest point at `contact`, if it is over the floor: an object's top."""
        height = float(contact.point[2]) - self.approaching.reach
        return height if height > self.container.floor + self.floor_band else None

    @staticmethod
    def _felt(contact: Contact) -> str:
        return f"{contact.sensor} {contact.force:.1f} N"

    def _estimated(self, readings: Readings, why: str) -> None:
        """The approach where the sweep placed the object, its top unknown (at least the sweep's height)."""
        self._approach(readings, self.swept.estimate,
                       f"the sweep felt it ({self._felt(self.swept.contact)}); {why}: its top unknown", False)

    def _approach(self, readings: Readings, point: np.ndarray, how: str, top: bool) -> None:
        """An object is felt at `point`: lift the hand off it, and where its `top` is known feel
        how far the top reaches each way (`_sides`) before saying where to grasp (`_conclude`)."""
        self.result = Finding(point, how, top)
        self.plan = [Waypoint(self.explore.rest + np.array([0.0, 0.0, LIFT_OFF]), Leg.LIFT)]
        if top:
            self.plan += self._sides(readings, point)

    def _sides(self, readings: Readings, point: np.ndarray) -> list[Waypoint]:
        """Over the top at `point` (world) and down beside it along each of the container's
        axes, both ways, the hand's tip (`sweep_extent`, the hand turned as it is) reaching to
        SIDE_STEP out and no nearer (a `spread_tip`'s to where it landed: which side is it
        under?), where that keeps the hand as far inside the walls as the sweep does, else
        (`_by_wall`) as near the wall as the tip fits (a spread tip's, only where it comes nearer
        its own axis's walls than the sweep: nearer the other axis's alone, it stays where it
        was, no deeper than the tip fits there, `_tip_depth`); from one side to the next
        SIDE_RISE over the top."""
        above = float(point[2]) + self.approaching.reach + SIDE_RISE
        low, high = self.container.footprint(self.room)
        centre = self.container.to_local(point[None])[0]
        tip = self._tip_along(readings)
        self.result.tip = tip
        past = 0.0 if self.spread else SIDE_STEP  # how far past where it landed the tip's near edge comes down
        legs = [Waypoint(np.array([*self.explore.rest[:2], above]), Leg.ABOVE)]
        for axis in (0, 1):
            for sign in (1, -1):
                local = centre.copy()
                local[axis] += sign * (past + tip[axis])
                depth = SIDE_DEPTH
                inside = (local[:2] >= low - 1e-9) & (local[:2] <= high + 1e-9)
                if self.spread and inside[axis] and not inside[1 - axis]:  # nearer the other axis's walls
                    depth = self._tip_depth(float(point[2]))
                elif not np.all(inside):
                    local[axis], depth = self._by_wall(centre, axis, sign, float(tip[axis]), float(point[2]),
                                                       0.0 if self.spread else float(tip[axis]))
                    if depth > 0.0:
                        self.result.by_wall.add((axis, sign))
                if depth <= 0.0:
                    continue  # a side the hand cannot come down at: not felt
                x, y, _ = self.container.to_world(local[None])[0]
                legs += [Waypoint(np.array([x, y, above]), Leg.ABOVE),
                         Waypoint(np.array([x, y, above - SIDE_RISE - depth]), Leg.SIDE, (axis, sign)),
                         Waypoint(np.array([x, y, above]), Leg.ABOVE)]
        return legs

    def _conclude(self) -> None:
        """The approach over what was felt: moved SIDE_STEP / 2 towards a side the top reaches
        where the other side's does not, SIDE_STEP where the hand's tip alone felt that side by
        a wall (no nearer the wall than the tip fits), and turned to close the jaws (along the
        hand's y) across the container's x where the top is long along its y and not along its
        x (`_long`), else across its y; a `spread_tip`'s moved under the tip's half the top is
        under (`_under_tip`) and turned as the walls leave the grasp room (`_roomiest`); at the
        half turn whose grasp the walls push less off it (`roomier_half`: the SDH2's thumb
        towards the room, as vision turns it)."""
        finding = self.result
        local = self.container.to_local(finding.point[None])[0]
        reaches = finding.reaches
        walled = []
        for axis in (0, 1):
            plus, minus = reaches.get((axis, 1)), reaches.get((axis, -1))
            if self.spread:
                local[axis] = self._under_tip(float(local[axis]), axis, plus, minus)
            elif plus is not None and minus is not None and plus != minus:
                sign = 1 if plus else -1
                if (axis, sign) in finding.by_wall:  # against the wall: as far towards it as the tip fits
                    room = self._wall_room(axis, float(np.max(self.tip)))
                    moved = sign * max(sign * local[axis], min(sign * local[axis] + SIDE_STEP, room))
                    walled.append(f"{abs(moved - local[axis]) * 100:.1f} cm towards the {'+' if sign > 0 else '-'}"
                                  f"{'xy'[axis]} wall")
                    local[axis] = moved
                else:
                    local[axis] += sign * SIDE_STEP / 2
        point = self.container.to_world(local[None])[0]
        point[2] = finding.point[2]
        yaw = self._roomiest(point) if self.spread else _across_long(reaches)
        times = self.tried.times + 1 if self.again else 0
        turn = TURNS[times % len(TURNS)]
        self.ctx.memory[TRIED] = Tried(point, times)
        yaw = roomier_half(self.container, point, yaw + turn, self.footprint[:2], self.footprint[2:])
        pose = approach_pose(self.container, point, self.approaching.grasp_reach, self.approaching.height, yaw)
        felt = ", ".join(f"{'+' if sign > 0 else '-'}{'xy'[axis]} {'yes' if on else 'no'}"
                         for (axis, sign), on in reaches.items())
        out = "under the tip's edge over where it landed" if self.spread else f"{SIDE_STEP * 100:g} cm out"
        how = finding.how + (f"; its top reaches {out}: {felt}" if felt else "")
        if walled:
            how += f"; its top goes on towards a wall: moved {', '.join(walled)}"
        if times:
            how += (f"; landed where the last approach lay ({times} in a row): the jaws turned "
                    f"{math.degrees(turn):g} deg")
        self.found(Approach(pose, point, self.method, top=float(point[2]) if finding.on_top else None,
                            either_way=not any(self.footprint[2:])), "", how)

    def _roomiest(self, point: np.ndarray) -> float:
        """Of closing the jaws across the container's y (yaw 0) and across its x, the one whose
        grasp over `point` (world) the walls push less off it along its closing axis
        (`walls_push`, each at its `roomier_half`): a spread tip's sides tell where the top lies,
        not how it is long."""
        extent, offset = self.footprint[:2], self.footprint[2:]

        def pushed(yaw: float) -> float:
            turned = roomier_half(self.container, point, yaw, extent, offset)
            pose = approach_pose(self.container, point, 0.0, 0.0, turned)
            return round(walls_push(self.container, pose, extent, offset)[0], 6)

        return min((0.0, math.pi / 2), key=pushed)

    def _under_tip(self, at: float, axis: int, plus: bool | None, minus: bool | None) -> float:
        """Where along the container's `axis` a spread tip that landed at `at` (its frame) has
        the top it felt: under the half of its reach on the likelier side (`plus`, `minus`: the
        top felt there, the side not felt at all, or the top not felt there, likeliest first),
        the tip's reach that way, where its fingertips are, within the container; where it
        landed where both sides are alike."""
        if plus is minus:
            return at
        likelier = (True, None, False)
        sign = 1 if likelier.index(plus) < likelier.index(minus) else -1
        half = float(self.container.inner[axis]) / 2
        return float(np.clip(at + sign * self.result.tip[axis], -half, half))

    def _wall_room(self, axis: int, tip: float) -> float:
        """How far from the container's middle along its `axis` the TCP may go with the hand's
        tip, reaching `tip` that way, WALL_CLEARANCE off the wall."""
        return float(self.container.footprint(tip + WALL_CLEARANCE)[1][axis])

    def _by_wall(self, centre: np.ndarray, axis: int, sign: int, tip: float, top: float,
                 past: float) -> tuple[float, float]:
        """For a side of the top at `centre` (the container's frame, world height `top`) where the
        walls keep the hand from coming down: where along `axis` its TCP comes as near the wall as
        the tip, reaching `tip` that way, fits, and how far below the top the tip may go down there
        with the hand's part wider than it (`tip_length` above its lowest point) WALL_CLEARANCE
        over the rim, at most SIDE_DEPTH; depth 0 where it cannot feel there (the top too low, or
        no room beside where it landed: the tip's near edge less than `past` beyond it)."""
        near = sign * self._wall_room(axis, tip)
        if sign * (near - centre[axis]) < tip + past:
            return near, 0.0
        return near, self._tip_depth(top)

    def _tip_depth(self, top: float) -> float:
        """How far below a top at world height `top` the hand's tip may go down beside it with
        the hand's part wider than the tip (`tip_length` above its lowest point) WALL_CLEARANCE
        over the rim, at most SIDE_DEPTH."""
        return max(0.0, min(SIDE_DEPTH, top + self.tip_length - self.container.rim - WALL_CLEARANCE))

    def _ahead(self, readings: Readings, contact: Contact, by_walls: bool) -> np.ndarray:
        """Where, at the sweep's height, the hand comes down to feel what the sweep met: its
        near side is where the hand's tip reaches along the sweep (`sweep_extent`, the hand
        turned as it is), and the hand comes down FEEL_INTO past it, kept inside the walls by
        its reach (`hand_radius`) as the lanes are, or `by_walls` by its tip's as going round them is."""
        way = contact.direction[:3] * np.array([1.0, 1.0, 0.0])
        way = way / np.linalg.norm(way)
        along_hand = np.abs(readings.tcp[:3, :3].T @ way)[:2]
        ahead = contact.point + (float(along_hand @ self.tip) + FEEL_INTO) * way
        local = self.container.to_local(ahead[None])[0]
        low, high = self.container.footprint(self._walls_room(readings) if by_walls else self.room)
        local[:2] = np.clip(local[:2], low, high)
        point = self.container.to_world(local[None])[0]
        point[2] = float(contact.point[2]) - self.approaching.reach  # its top is at least that high
        return point

    def _feel(self, readings: Readings, swept: Swept) -> list[Waypoint]:
        """Back off what the sweep met, up just over the rim, over where it lies, and down onto
        it: by the walls no lower than the hand went round them (`_walls_tcp`)."""
        back = readings.tcp[:3, 3] - BACK_OFF * swept.contact.direction
        over = self._over_rim()
        x, y = swept.estimate[:2]
        down = self._walls_tcp() if swept.by_walls else self._below_floor()
        return [Waypoint(back, Leg.RETREAT), Waypoint(np.array([back[0], back[1], over]), Leg.RETREAT),
                Waypoint(np.array([x, y, over]), Leg.RETREAT), Waypoint(np.array([x, y, down]), Leg.FEEL)]

    def _tip_along(self, readings: Readings) -> np.ndarray:
        """How far the hand's tip (`sweep_extent`, the hand turned as it is) reaches along
        each of the container's x and y."""
        return self._along_box(readings.tcp[:3, :3], self.tip)

    def _along_box(self, rotation: np.ndarray, reach: np.ndarray) -> np.ndarray:
        """How far a hand turned as `rotation` (world), reaching `reach` along its x and its y,
        reaches along each of the container's x and y."""
        return np.abs(rotation.T @ self.container.pose[:3, :2])[:2].T @ reach

    def _sweep(self, readings: Readings) -> list[Waypoint]:
        """Up to the sweep's height, then lanes along the container's x, `lane_spacing` apart
        at most, from the corner nearest the hand; then round the walls (`_along_walls`)."""
        here = readings.tcp[:3, 3]
        height = self.container.floor + self.sweep_height + self.approaching.reach
        low, high = self.container.footprint(self.room)
        local = self.container.to_local(here[None])[0]
        lanes = max(1, math.ceil((high[1] - low[1]) / self.lane_spacing) + 1) if high[1] > low[1] else 1
        ys = np.linspace(low[1], high[1], lanes)
        if abs(local[1] - high[1]) < abs(local[1] - low[1]):
            ys = ys[::-1]
        ends = (low[0], high[0]) if abs(local[0] - low[0]) <= abs(local[0] - high[0]) else (high[0], low[0])
        points = []
        for lane, y in enumerate(ys):
            first, last = ends if lane % 2 == 0 else ends[::-1]
            points += [(first, y), (last, y)]
        world = self.container.to_world(np.array([[x, y, 0.0] for x, y in points]))
        world[:, 2] = height
        return ([Waypoint(np.array([here[0], here[1], height]), Leg.TRANSIT)] + [Waypoint(p, Leg.SWEEP) for p in world]
                + self._along_walls(readings, world[-1]))

    def _along_walls(self, readings: Readings, end: np.ndarray) -> list[Waypoint]:
        """From the lanes' `end` (world), along the walls: the lanes keep the whole hand
        `hand_radius` off them, and an object lying in the band they leave (docs/empty-the-box.md:
        a spray can 2.6 cm from a wall) is felt only there. Along each wall where the ring
        (`_ring`) would pass over the lowest object (LOWEST_TOP) and the hand, turned its
        narrower way, fits nearer it than the lanes at their height (`_low_walls`); round the
        rest in the ring."""
        if self.walls_height is None:
            return []
        legs, self.walled = self._low_walls(readings, end)
        if len(self.walled) == 2:
            return legs
        turns = [leg.turn for leg in legs if leg.kind is Leg.TURN]
        if turns and turns[-1]:  # the ring is laid for the hand as the look began
            over = np.array([*legs[-1].to[:2], self._clear()])
            legs += [Waypoint(over, Leg.RISE), Waypoint(over, Leg.TURN)]
        return legs + self._ring(readings, legs[-1].to if legs else end)

    def _low_walls(self, readings: Readings, end: np.ndarray) -> tuple[list[Waypoint], set[int]]:
        """From `end` (world), along the walls across each of the container's axes (0 x, 1 y)
        the hand can go along at the lanes' height nearer them than the lanes did, turned (a
        quarter turn or none) so its whole extent (`hand_extent`) towards them is the smaller,
        the whole hand WALLS_CLEARANCE off every wall, each wall from its end nearer the hand;
        and the axes done. At the lanes' height from one wall to the next, where the hand fits
        all the way as it does at both ends (what it meets is an object ahead, placed as by the
        walls: the SDH2's lanes are a point in the middle); over the rim to turn, and down
        from there. None where the ring comes under LOWEST_TOP or the hand's extent is not
        known."""
        if self.walls_height < LOWEST_TOP or not np.all(self.extent > 0.0):
            return [], set()
        rotation = readings.tcp[:3, :3]
        height = self.container.floor + self.sweep_height + self.approaching.reach
        here, legs, walled, now, low = end, [], set(), 0.0, True
        for axis in (0, 1):
            fits = []
            for turn in (0.0, math.pi / 2):
                room = self._along_box(_turned(rotation, turn), self.extent) + WALLS_CLEARANCE
                if room[axis] < self.room and room[1 - axis] < self.container.inner[1 - axis] / 2:
                    fits.append((float(room[axis]), turn, room))
            if not fits:
                continue
            _, turn, room = min(fits, key=lambda fit: fit[0])
            walled.add(axis)
            if turn != now:
                over = np.array([here[0], here[1], self._clear()])
                legs += [Waypoint(over, Leg.RISE), Waypoint(over, Leg.TURN, turn=turn)]
                now, low = turn, False
            lower, upper = self.container.footprint(room)
            nearer = self.container.to_local(here[None])[0][axis]
            for at in sorted((lower[axis], upper[axis]), key=lambda a: abs(a - nearer)):
                local = self.container.to_local(here[None])[0]
                ends = sorted((lower[1 - axis], upper[1 - axis]), key=lambda a: abs(a - local[1 - axis]))
                points = np.zeros((2, 3))
                points[:, axis], points[:, 1 - axis] = at, ends
                first, last = self.container.to_world(points)
                first[2] = last[2] = height
                if low:
                    legs.append(Waypoint(first, Leg.WALLS))
                else:
                    legs += [Waypoint(np.array([first[0], first[1], self._clear()]), Leg.TRANSIT),
                             Waypoint(np.array([first[0], first[1], self._over_rim()]), Leg.DOWN),
                             Waypoint(first, Leg.DOWN)]
                legs.append(Waypoint(last, Leg.WALLS))
                here, low = last, True
        return legs, walled

    def _ring(self, readings: Readings, end: np.ndarray) -> list[Waypoint]:
        """From `end` (world), up and round the container's walls, from the corner nearest it.
        The TCP keeps the hand's tip WALLS_CLEARANCE off each wall, its lowest point as low as
        keeps its wider part (`tip_length` above it) WALL_CLEARANCE over the rim, and no lower
        than the lanes (`walls_height`)."""
        height = self._walls_tcp()
        low, high = self.container.footprint(self._walls_room(readings))
        corners = np.array([[low[0], low[1]], [high[0], low[1]], [high[0], high[1]], [low[0], high[1]]])
        nearest = int(np.argmin(np.linalg.norm(corners - self.container.to_local(end[None])[0][:2], axis=1)))
        ring = np.roll(corners, -nearest, axis=0)
        world = self.container.to_world(np.array([[x, y, 0.0] for x, y in [*ring, ring[0]]]))
        world[:, 2] = height
        return [Waypoint(np.array([end[0], end[1], height]), Leg.TRANSIT)] + [Waypoint(p, Leg.WALLS) for p in world]

    def _walls_room(self, readings: Readings) -> np.ndarray:
        """How far the TCP keeps from the walls going round them: the tip's reach along each
        of the container's x and y, and WALLS_CLEARANCE; no further than the lanes."""
        return np.minimum(self._tip_along(readings) + WALLS_CLEARANCE, self.room)

    def _walls_tcp(self) -> float:
        """The TCP's height with the hand's lowest point `walls_height` over the floor."""
        return self.container.floor + self.walls_height + self.approaching.reach


def _turned(rotation: np.ndarray, angle: float) -> np.ndarray:
    """`rotation` (3x3, world) turned `angle` (rad) about the world vertical."""
    return axis_rotation(VERTICAL, angle) @ rotation


def _across_long(reaches: dict[tuple[int, int], bool]) -> float:
    """The yaw (from the container's x) of jaws closing along the hand's y across a top that
    reaches out as `reaches` says: across the container's x where it is long along its y and not
    along its x (`_long`), else across its y."""
    along = [_long(reaches.get((axis, 1)), reaches.get((axis, -1))) for axis in (0, 1)]
    return math.pi / 2 if along[1] and not along[0] else 0.0


def _long(plus: bool | None, minus: bool | None) -> bool:
    """Whether a top is long along an axis from whether it reaches out that way on either side
    (None: a side the hand could not come down at, by a wall): it reaches out on one side and
    is not known to stop on the other."""
    return (plus is True or minus is True) and plus is not False and minus is not False
