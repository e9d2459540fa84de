"""Leaf conditions: every condition kind of the vocabulary, from the robot's own sensors.

Each leaf answers `holds` every control tick (the executor never short-circuits, so
debounce timers see every tick) and keeps in `evidence` the readings behind its latest
verdict, which the trace records when the event fires. Sensor names in a leaf are the
factory's (`tactile_left`, `wrist_ft`, `gripper`, ...); `pad_indices` finds the robot's
pad behind each tactile name.
"""

from __future__ import annotations

import math
from abc import abstractmethod
from typing import Any

import numpy as np

from atd.model.frames import GRAVITY
from primitives.base import Condition, Context, StateView, Status
from primitives.blackboard import EMPTY_HAND
from primitives.filters import ContactWrench, Debounce, LowPass, PressureCentres, RecentRows, world_load
from primitives.hands.posture import REACHED
from primitives.robot import HandInfo, Readings
from primitives.values import Approach, NothingFound

# hardware_failure ingredients (ours)
STALE_TIME = 0.05  # s a sensor stream may go without an update before it counts as frozen
LIMIT_MARGIN = 1e-3  # rad or m: a joint this close to a limit sits on it
LIMIT_TIME = 0.2  # s on a limit before it counts as stuck there
RUNAWAY_SPEED = 3.0  # times the joint speed limit: the physics has run away
RUNAWAY_FORCE = 1e4  # N on the wrist
RUNAWAY_DISTANCE = 10.0  # m of the TCP from the world origin


def pad_indices(hand: HandInfo, sensors: tuple[str, ...]) -> list[int]:
    """The robot pads behind the factory's tactile sensor names (a factory names its
    tactile sensors as the robot description names its pads)."""
    names = [p.name for p in hand.pads]
    missing = [s for s in sensors if s not in names]
    if missing:
        raise ValueError(f"tactile sensor '{missing[0]}' names no pad of this hand (pads: {', '.join(names) or 'none'})")
    return [names.index(s) for s in sensors]


class StatusIs(Condition):
    """A controller (or sub-task) has reached a status, and kept it for `for_time` where
    the kind takes one: the `*_done`, `*_error`, `subtask_*` kinds."""

    def __init__(self, ctx: Context, sensors: tuple[str, ...], which: str, status: Status) -> None:
        super().__init__(ctx, sensors)
        self.which, self.status = which, status
        self.debounce = Debounce(float(self.params.get("for_time", 0.0)))
        self.seen: tuple[StateView, float] | None = None  # the view and the time held at the latest verdict that held

    def start(self, readings: Readings) -> None:
        self.debounce.reset()

    def holds(self, readings: Readings, state: StateView, dt: float) -> bool:
        if not self.debounce(getattr(state, self.which) is self.status, dt):
            return False
        self.seen = (state, self.debounce.held)
        return True

    @property
    def evidence(self) -> dict[str, Any]:
        """Worked out when asked (the tick an event fires), not on every tick the status holds."""
        if self.seen is None:
            return {}
        state, held = self.seen
        return {self.which: self.status.value, "reason": state.reasons.get(self.which, ""),
                **state.counts.get(self.which, {}), "held_for": held}


class SubtaskEndedIn(Condition):
    """The sub-task's machine ended in the end state `end_state`: a parent branching on
    which of its outcomes a sub-task reached (an ATD `<outcome name="..."/>`)."""

    def holds(self, readings: Readings, state: StateView, dt: float) -> bool:
        if state.subtask_end != self.params["end_state"]:
            return False
        self.evidence = {"subtask_end": state.subtask_end}
        return True


class Timeout(Condition):
    def __init__(self, ctx: Context, sensors: tuple[str, ...] = ()) -> None:
        super().__init__(ctx, sensors)
        self.limit = float(self.params["seconds"])
        self.elapsed = 0.0  # s in the state at the latest verdict

    def holds(self, readings: Readings, state: StateView, dt: float) -> bool:
        self.elapsed = state.elapsed
        return state.elapsed >= self.limit - 1e-9

    @property
    def evidence(self) -> dict[str, Any]:
        return {"elapsed": self.elapsed, "seconds": self.limit}


class Fault(Condition):
    """A hardware failure on one side: its controller reports FAULT, one of its sensor
    streams stopped updating (`Readings.seq`), or (arm) a joint is stuck on a limit."""

    def __init__(self, ctx: Context, sensors: tuple[str, ...], side: str, streams: tuple[str, ...]) -> None:
        super().__init__(ctx, sensors)
        self.side, self.streams = side, streams
        info = ctx.info
        self.lower = info.arm_lower + LIMIT_MARGIN
        self.upper = info.arm_upper - LIMIT_MARGIN
        self.on_limit = Debounce(LIMIT_TIME)

    def start(self, readings: Readings) -> None:
        self.seq = {s: readings.seq.get(s, 0) for s in self.streams}
        self.updated = dict.fromkeys(self.streams, readings.time)
        self.on_limit.reset()

    def holds(self, readings: Readings, state: StateView, dt: float) -> bool:
        if getattr(state, self.side) is Status.FAULT:
            self.evidence = {self.side: "fault", "reason": state.reasons.get(self.side, "")}
            return True
        now = readings.time
        for stream in self.streams:
            seq = readings.seq.get(stream, 0)
            if seq != self.seq[stream]:
                self.seq[stream], self.updated[stream] = seq, now
            elif now - self.updated[stream] > STALE_TIME:
                self.evidence = {"frozen_sensor": stream, "seq": seq, "last_update": self.updated[stream]}
                return True
        if self.side == "arm":
            q = readings.arm_q
            stuck = (q <= self.lower) | (q >= self.upper)
            if self.on_limit(np.count_nonzero(stuck) > 0, dt):
                joint = self.ctx.info.arm_joints[int(np.argmax(stuck))]
                self.evidence = {"joint_on_limit": joint, "q": q[np.argmax(stuck)], "for": self.on_limit.held}
                return True
        return False


class SimulationUnstable(Condition):
    """The physics diverged: a non-finite reading, or joints, wrench or TCP far beyond
    anything a working robot shows. A joint that jumps further in one tick than its speed
    allows counts too: an engine that meets NaNs may reset its state (MuJoCo does), and
    the jump is all a sensor sees of that."""

    def __init__(self, ctx: Context, sensors: tuple[str, ...] = ()) -> None:
        super().__init__(ctx, sensors)
        self.max_speed = (RUNAWAY_SPEED * ctx.info.arm_velocity_limit).tolist()

    def start(self, readings: Readings) -> None:
        self.last_q = readings.arm_q

    def holds(self, readings: Readings, state: StateView, dt: float) -> bool:
        r = readings
        parts = (r.arm_q, r.arm_dq, r.hand_q, r.wrench, r.tcp[:3, 3])
        if not math.isfinite(float(np.concatenate(parts).sum())):  # a NaN or inf anywhere spoils the sum
            names = ("arm_q", "arm_dq", "hand_q", "wrench", "tcp")
            self.evidence = {name: p for name, p in zip(names, parts) if not np.isfinite(p).all()}
            self.evidence["non_finite"] = ", ".join(self.evidence)
            return True
        last, self.last_q = self.last_q, r.arm_q
        # Joint by joint in plain floats (all finite here): cheaper than numpy's calls on a few joints.
        for q, before, speed, limit in zip(r.arm_q.tolist(), last.tolist(), r.arm_dq.tolist(), self.max_speed):
            if abs(speed) - limit > 0.0 or abs(q - before) / dt - limit > 0.0:
                self.evidence = {"runaway_joint_speed": r.arm_dq, "joint_jump": np.abs(r.arm_q - last)}
                return True
        force, where = r.wrench[:3], r.tcp[:3, 3]
        if float(force.dot(force)) > RUNAWAY_FORCE ** 2 or float(where.dot(where)) > RUNAWAY_DISTANCE ** 2:
            self.evidence = {"runaway_wrench": r.wrench, "tcp": where}
            return True
        return False


class Debounced(Condition):
    """A sensor test that must hold for `for_time` without a break."""

    def __init__(self, ctx: Context, sensors: tuple[str, ...]) -> None:
        super().__init__(ctx, sensors)
        self.debounce = Debounce(float(self.params.get("for_time", 0.0)))

    def start(self, readings: Readings) -> None:
        self.debounce.reset()

    def holds(self, readings: Readings, state: StateView, dt: float) -> bool:
        return self.debounce(self.test(readings, dt), dt)

    @property
    def evidence(self) -> dict[str, Any]:
        """Worked out when asked (the tick an event fires), not on every tick's test."""
        return {**self.explain(), "held_for": max(self.debounce.held, 0.0)}

    @abstractmethod
    def test(self, readings: Readings, dt: float) -> bool:
        """The undebounced verdict; keeps what `explain` needs."""

    @abstractmethod
    def explain(self) -> dict[str, Any]:
        """The readings behind the latest `test`."""


class TactileForce(Debounced):
    """At least `min_pads` of the named pads read >= `force_threshold` (above), or fewer
    do (below)."""

    def __init__(self, ctx: Context, sensors: tuple[str, ...], above: bool) -> None:
        super().__init__(ctx, sensors)
        self.pads = pad_indices(ctx.info.hand, sensors)
        self.threshold = float(self.params["force_threshold"])
        self.min_pads = int(self.params["min_pads"])
        self.above = above

    def test(self, readings: Readings, dt: float) -> bool:
        self.forces = readings.pad_force[self.pads].tolist()  # a few pads: plain floats are cheaper than array ops
        touching = sum(force >= self.threshold for force in self.forces)
        return (touching >= self.min_pads) == self.above

    def explain(self) -> dict[str, Any]:
        return {"pad_force": dict(zip(self.sensors, self.forces)), "threshold": self.threshold, "min_pads": self.min_pads}


class TactileLoadChange(Debounced):
    """The summed pad force moved by more than `force_change` since the state began: the
    held object touched something."""

    def __init__(self, ctx: Context, sensors: tuple[str, ...]) -> None:
        super().__init__(ctx, sensors)
        self.pads = pad_indices(ctx.info.hand, sensors)
        self.change = float(self.params["force_change"])

    def start(self, readings: Readings) -> None:
        super().start(readings)
        self.initial = float(readings.pad_force[self.pads].sum())

    def test(self, readings: Readings, dt: float) -> bool:
        self.total = float(readings.pad_force[self.pads].sum())
        return abs(self.total - self.initial) > self.change

    def explain(self) -> dict[str, Any]:
        return {"pad_force_sum": self.total, "at_start": self.initial, "force_change": self.change}


class WristForceAbove(Debounced):
    """The contact wrench (tared at the state's start, filtered) exceeds the threshold:
    its force norm, or minus its hand-z force (the hand pushed back)."""

    def __init__(self, ctx: Context, sensors: tuple[str, ...]) -> None:
        super().__init__(ctx, sensors)
        self.threshold = float(self.params["force_threshold"])
        self.axis = str(self.params["axis"])
        self.contact = ContactWrench(float(self.params["filter_time"]))

    def start(self, readings: Readings) -> None:
        super().start(readings)
        self.contact.start(readings)

    def test(self, readings: Readings, dt: float) -> bool:
        self.wrench = wrench = self.contact.update(readings, dt)
        self.value = self.contact.force if self.axis == "norm" else -float(wrench[2])
        return self.value > self.threshold

    def explain(self) -> dict[str, Any]:
        return {"force": self.value, "axis": self.axis, "threshold": self.threshold, "contact_wrench": self.wrench}


class LoadHeld(Debounced):
    """The wrist carries at least `weight` beyond the empty hand's load as the latest
    grasp began (`EMPTY_HAND`): the object is held, not just touched, once it has left its
    support. Averaged over `filter_time`: a hand speeding up reads as load too. Without an
    empty-hand reading (no grasp yet in this run) there is nothing to judge by: it does
    not hold."""

    def __init__(self, ctx: Context, sensors: tuple[str, ...]) -> None:
        super().__init__(ctx, sensors)
        self.weight = float(self.params["weight"])
        self.load = LowPass(float(self.params["filter_time"]))

    def start(self, readings: Readings) -> None:
        super().start(readings)
        self.load.reset(world_load(readings))

    def test(self, readings: Readings, dt: float) -> bool:
        empty = self.ctx.memory.get(EMPTY_HAND)
        load = self.load(world_load(readings), dt)
        if empty is None:
            self.carried: float | None = None
            return False
        self.carried = float(empty[2] - load[2]) / GRAVITY  # kg: a weight pulls the wrist down, along world -z
        return self.carried >= self.weight

    def explain(self) -> dict[str, Any]:
        if self.carried is None:
            return {"empty_hand": "never measured"}
        return {"carried": round(self.carried, 3), "weight": self.weight}


class FingersPressing(Debounced):
    """A closing joint of the hand presses on something short of the hand's `posture`: its
    effort in the closing direction is at least `effort` of its limit, and it stands more
    open than the posture by more than a hand posture's REACHED. Something stands between
    the fingers (a look's close held by what the hand still grips: docs/empty-the-box.md);
    a hand that made the posture is not blocked, however hard it presses there (the SDH2's
    `closed` presses 9 % of its limit on nothing). A multi-finger hand still closing from
    open presses so too (up to 24 % of its limit): no stillness is asked, since a Melfa's
    jaws squeezing a held block closed on at 8 mm/s while its look gave up."""

    def __init__(self, ctx: Context, sensors: tuple[str, ...]) -> None:
        super().__init__(ctx, sensors)
        hand = ctx.info.hand
        self.closing = hand.closing
        self.least = float(self.params["effort"]) * hand.effort_limit
        self.goal = np.asarray(hand.postures[str(self.params["posture"])], float)
        self.tolerance = REACHED * (hand.upper - hand.lower)
        self.pressing = np.zeros_like(self.least)
        self.short = np.zeros_like(self.goal)

    def test(self, readings: Readings, dt: float) -> bool:
        self.pressing = np.where(self.closing != 0, self.closing * readings.hand_effort, 0.0)
        self.short = self.closing * (self.goal - readings.hand_q)
        return bool(((self.pressing >= self.least) & (self.short > self.tolerance)).any())

    def explain(self) -> dict[str, Any]:
        return {"closing_effort": [round(float(e), 4) for e in self.pressing],
                "least": [round(float(e), 4) for e in self.least],
                "short_of_posture": [round(float(v), 4) for v in self.short]}


class FingersStill(Debounced):
    """Every closing joint of the hand moves slower than `drift` of its travel per second:
    a grip that keeps closing is squeezing the object out of the hand (a duck or a tape
    roll crept 3-4 mm/s between the jaws while the grip force held steady). The speed is
    that of the low-passed joint positions, (q - q_filtered) / filter_time, not the
    velocity reading: a force-controlled grip chatters about a still mean, and in PyBullet
    the SDH2's fingers vibrate at +-2.6 rad/s, aliased by the control rate into what reads
    as a steady speed, while their positions stay within 2 mrad. The joints' spread over the
    last `filter_time` must be as small: where a grip that opened during the lift turns to
    closing, the low-passed mean catches up with the position and the lag alone reads
    still (a Baxter gripper squeezing a duck out at 2.7 mm/s did, in 0.4 mm encoder steps)."""

    def __init__(self, ctx: Context, sensors: tuple[str, ...]) -> None:
        super().__init__(ctx, sensors)
        hand = ctx.info.hand
        self.joints = np.flatnonzero(hand.closing)
        self.travel = (hand.upper - hand.lower)[self.joints]
        self.drift = float(self.params["drift"])
        self.tau = float(self.params["filter_time"])
        self.mean = LowPass(self.tau)
        self.recent = RecentRows(len(self.joints))

    def start(self, readings: Readings) -> None:
        super().start(readings)
        self.mean.reset(readings.hand_q[self.joints])
        self.recent.clear()

    def test(self, readings: Readings, dt: float) -> bool:
        q = readings.hand_q[self.joints]
        self.recent.add(readings.time, q, readings.time - self.tau)
        rows = self.recent.rows()
        spread = (rows.max(axis=0) - rows.min(axis=0)) / max(self.tau, dt)  # np.ptp without its wrappers
        speed = np.maximum(np.abs(q - self.mean(q, dt)) / max(self.tau, dt), spread)
        self.rate = float((speed / self.travel).max(initial=0.0))
        return self.rate < self.drift

    def explain(self) -> dict[str, Any]:
        return {"drift": round(self.rate, 4), "still_below": self.drift}


class SlipWatched(Debounced):
    """The pads' contacts have not moved across them while the arm holds at its target, or
    have been watched `watch` since they first did: a grip whose contacts travel while the
    hand holds still may be letting the object turn or slide out, and one that does drops it
    within the watch (docs/robust-grasp.md, "A slipping grip watched on the taxels"). A
    contact on the line between two taxels flickers from one to the other while the object
    stays put, so a move starts the watch once rather than a stillness the watch must wait
    for. Only pads with a taxel array are read; a pad pressing nothing has no centre."""

    def __init__(self, ctx: Context, sensors: tuple[str, ...]) -> None:
        super().__init__(ctx, sensors)
        self.centres = PressureCentres([ctx.info.hand.pads[i] for i in pad_indices(ctx.info.hand, sensors)])
        self.names = self.centres.names
        self.distance = float(self.params["distance"])
        self.watch = float(self.params["watch"])

    def start(self, readings: Readings) -> None:
        super().start(readings)
        self.low = np.full((len(self.names), 2), np.inf)  # each pad's centre, least and most, over the hold
        self.high = -self.low
        self.moved = np.zeros(len(self.names))
        self.moved_at: float | None = None  # when a centre first moved more than `distance`
        self.time = readings.time

    def holds(self, readings: Readings, state: StateView, dt: float) -> bool:
        """Watched only while the arm holds at its target: a moving arm shifts the load on the pads."""
        if state.arm is not Status.DONE:
            return self.debounce(True, dt)
        return super().holds(readings, state, dt)

    def test(self, readings: Readings, dt: float) -> bool:
        self.time = readings.time
        if self.moved_at is None:
            centre = self.centres(readings)
            pressed = ~np.isnan(centre[:, 0])
            self.low[pressed] = np.minimum(self.low[pressed], centre[pressed])
            self.high[pressed] = np.maximum(self.high[pressed], centre[pressed])
            self.moved[pressed] = np.hypot(*(self.high[pressed] - self.low[pressed]).T)
            if self.moved.max(initial=0.0) > self.distance:
                self.moved_at = readings.time
        return self.moved_at is None or readings.time - self.moved_at >= self.watch

    def explain(self) -> dict[str, Any]:
        moved = {name: round(float(m), 4) for name, m in zip(self.names, self.moved)}
        if self.moved_at is None:
            return {"moved": moved, "still_within": self.distance}
        return {"moved": moved, "watched": round(self.time - self.moved_at, 3), "watch": self.watch}


class Gripper(Debounced):
    """A parallel gripper's own sensing: motor force (N, along closing) or jaw opening
    (m between the pads, beyond the closed gap), compared with a threshold."""

    def __init__(self, ctx: Context, sensors: tuple[str, ...], quantity: str, above: bool) -> None:
        super().__init__(ctx, sensors)
        hand = ctx.info.hand
        if len(hand.dofs) != 1:
            raise ValueError(f"gripper sensing needs a one-DOF parallel gripper; this hand has {len(hand.dofs)} DOFs")
        self.closing, self.closed = float(hand.closing[0]), float(hand.closed[0])
        self.quantity, self.above = quantity, above
        self.threshold = float(self.params["force_threshold" if quantity == "force" else "width"])

    def test(self, readings: Readings, dt: float) -> bool:
        if self.quantity == "force":
            value = max(0.0, self.closing * float(readings.hand_effort[0]))
        else:
            value = 2.0 * abs(float(readings.hand_q[0]) - self.closed)  # both jaws move
        self.value = value
        return (value > self.threshold) if self.above else (value < self.threshold)

    def explain(self) -> dict[str, Any]:
        return {self.quantity: self.value, "threshold": self.threshold}


class Range(Debounced):
    """The range sensor along the approach axis reads below / above a distance (inf =
    nothing in range)."""

    def __init__(self, ctx: Context, sensors: tuple[str, ...], above: bool) -> None:
        super().__init__(ctx, sensors)
        if not ctx.info.has_range:
            raise ValueError("this robot has no range sensor")
        self.distance = float(self.params["distance"])
        self.above = above

    def test(self, readings: Readings, dt: float) -> bool:
        self.value = value = math.inf if readings.range is None else float(readings.range)
        return (value > self.distance) if self.above else (value < self.distance)

    def explain(self) -> dict[str, Any]:
        return {"range": self.value if math.isfinite(self.value) else "out of range", "distance": self.distance}


class Perceived(Condition):
    """The state's perceive controller has finished and written what it found under `value`:
    an object (`Approach`, for object_found) or none (`NothingFound`, for nothing_found)."""

    def __init__(self, ctx: Context, sensors: tuple[str, ...], kind: type[Approach] | type[NothingFound]) -> None:
        super().__init__(ctx, sensors)
        self.value = str(self.params["value"])
        self.kind = kind

    def holds(self, readings: Readings, state: StateView, dt: float) -> bool:
        found = self.ctx.memory.get(self.value)
        if state.arm is not Status.DONE or not isinstance(found, self.kind):
            return False
        self.evidence = ({"value": self.value, "point": found.point, "method": found.method}
                         if isinstance(found, Approach) else {"value": self.value, "nothing": found.reason})
        return True
