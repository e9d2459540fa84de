"""Blind exploration (thesis 3.4.3, Fig. 3.26a): find an object in the container by touch.

A plan of `explore` moves. The hand comes over a point of the container's floor drawn at
random, clear of its rim, and goes down until it feels something. A contact above the floor
(the floor's height is the container's believed pose; the contact's, the TCP's height less
the hand's reach) is an object's top: the approach is there. The floor itself starts a
sweep: the hand, its lowest point just above the floor, goes along the container in lanes
(a boustrophedon) until it feels something, which is an object ahead of it; a sweep that
feels nothing found nothing.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from primitives.arm.approach_phases import SETTLE
from primitives.arm.explore import ARRIVED, Explore
from primitives.base import Context, ControlData, Status
from primitives.perception.container import approach_pose
from primitives.perception.perceiver import Perceiver
from primitives.robot import Readings
from primitives.values import Approach, Contact

PROBE_BEYOND = 0.02  # m below the believed floor the probe goes before it gives up: the floor is not there
# m beyond where a sweep felt an object that its middle is taken to be: the contact is its near
# side, `hand_radius` ahead of the TCP; its size is not known
OBJECT_BEYOND = 0.02


@dataclass(frozen=True)
class Waypoint:
    """Where the next explore move goes, and what a contact on the way means: `transit`
    (over the container: something in the way, an error), `probe` (down onto the floor: an
    object, or the floor) or `sweep` (along the floor: an object)."""

    to: np.ndarray  # (3,), world, the TCP's
    kind: str


class BlindExploration(Perceiver):
    """The blind exploration generator as a controller: each explore move tared afresh from a
    hand held still for SETTLE after the one before, as the robust grasp does after its moves
    (stopping jolts the wrist by a few newtons)."""

    method = "blind_exploration"

    def __init__(self, ctx: Context) -> None:
        super().__init__(ctx)
        p = self.params
        self.margin = float(p["hand_radius"])
        self.sweep_height = float(p["sweep_height"])
        self.lane_spacing = float(p["lane_spacing"])
        self.floor_band = float(p["floor_band"])
        inner = self.container.inner
        if np.any(inner[:2] <= 2 * self.margin):
            raise ValueError(f"a hand reaching {self.margin:g} m sideways cannot sweep a container "
                             f"{inner[0]:g} x {inner[1]:g} m inside without touching its walls")
        self.moving = {"speed": p["speed"], "force_threshold": p["force_threshold"], "filter_time": p["filter_time"]}

    def start(self, readings: Readings) -> None:
        super().start(readings)
        here = readings.tcp[:3, 3]
        reach = self.approaching.reach
        clear = max(float(here[2]), self.container.rim + self.approaching.height + reach)
        low, high = self.container.footprint(self.margin)
        probe = self.container.to_world(np.array([[*self.ctx.rng.uniform(low, high), 0.0]]))[0]
        floor = self.container.floor + reach - PROBE_BEYOND
        self.plan = [Waypoint(np.array([here[0], here[1], clear]), "transit"),
                     Waypoint(np.array([probe[0], probe[1], clear]), "transit"),
                     Waypoint(np.array([probe[0], probe[1], floor]), "probe")]
        self.explore: Explore | None = None
        self._next(readings)

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
        while self.plan and np.linalg.norm(self.plan[0].to - here) < ARRIVED:
            self.plan.pop(0)
        if not self.plan:
            self.found(None, f"swept the container's floor {self.sweep_height * 100:g} cm above it without a contact")
            return
        self.leg = self.plan.pop(0)
        way = self.leg.to - here
        distance = float(np.linalg.norm(way))
        self.explore = Explore(replace(self.ctx, params={**self.moving, "direction": tuple(way / distance),
                                                         "max_distance": distance}))
        self.explore.start(readings)
        self.handled = False

    def _ended(self, readings: Readings) -> None:
        """What the explore move just ended tells: go on, found, or give up."""
        contact, kind = self.explore.found, self.leg.kind
        if kind == "transit" and contact is not None:
            x, y, z = contact.point
            self.finish(Status.ERROR, f"something in the way over the container: a contact at ({x:.3f}, {y:.3f}, "
                                      f"{z:.3f}) on the way to the probe")
        elif kind == "probe" and contact is None:
            self.finish(Status.ERROR, f"no floor within {PROBE_BEYOND * 100:g} cm below where the container's "
                                      f"floor is believed to be ({self.container.floor:.3f} m)")
        elif kind == "probe":
            height = float(contact.point[2]) - self.approaching.reach
            if height > self.container.floor + self.floor_band:
                self._approach(contact, np.array([*contact.point[:2], height]))
            else:
                self.plan = self._sweep(readings)
        elif contact is not None:
            ahead = contact.point[:2] + (self.margin + OBJECT_BEYOND) * contact.direction[:2]
            local = self.container.to_local(np.array([[*ahead, self.container.floor]]))[0]
            low, high = self.container.footprint(OBJECT_BEYOND)
            local[:2] = np.clip(local[:2], low, high)  # an object's middle lies inside the walls
            point = self.container.to_world(local[None])[0]
            point[2] = float(contact.point[2]) - self.approaching.reach  # its top is at least that high
            self._approach(contact, point)

    def _approach(self, contact: Contact, point: np.ndarray) -> None:
        pose = approach_pose(self.container, point, self.approaching.grasp_reach, self.approaching.height)
        self.found(Approach(pose, point, self.method), "", f"the {self.leg.kind} felt it: {contact.sensor} "
                                                           f"{contact.force:.1f} N")

    def _sweep(self, readings: Readings) -> list[Waypoint]:
        """Up to the sweep's height, then lanes along the container's x, `lane_spacing` apart
        at most, from the corner nearest the hand."""
        here = readings.tcp[:3, 3]
        height = self.container.floor + self.sweep_height + self.approaching.reach
        low, high = self.container.footprint(self.margin)
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
        return [Waypoint(np.array([here[0], here[1], height]), "transit")] + [Waypoint(p, "sweep") for p in world]
