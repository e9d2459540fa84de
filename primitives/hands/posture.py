"""Hand postures every hand can take, whatever its kind: stay, go to a named D5 hand shape,
open to a fraction of the stroke. They only move DOF values between the limits and the
postures `RobotInfo.hand` gives, so one implementation serves every hand."""

from __future__ import annotations

import numpy as np

from atd.model.controllers import CREEP_WATCH, SLIP_DISTANCE
from atd.model.vocabulary import HandShape as Shape
from primitives.base import Context, ControlData, Controller, HandCommand, Status
from primitives.blackboard import STEEP_PINCH
from primitives.filters import PressureCentres, RecentRows
from primitives.robot import HandMode, Readings

PRESHAPES = frozenset(s.value for s in Shape if s.value.endswith("_preshape"))

REACHED = 0.02  # of a DOF's range: close enough to the goal
STALL_TIME = 1.0  # s stopped short of the goal: something blocks the fingers
STILL_SPEED = 0.05  # of a DOF's speed limit: a finger slower than this on average has stopped
LOADED = 0.05  # of a DOF's effort limit, in the closing direction: the finger presses on something
STEEP_WATCH = CREEP_WATCH  # s a steep pinch is held before the hand says it holds
STEADY_WINDOW = 1.0  # s over which a watched pinch's pads must have kept their grip
# Of the pads' summed force per second a watched pinch may lose and count as steady: at 6 s the
# Barrett's lasting pinches eased 0-0.6 %/s, its creeping ones 1.6-4.4 %/s, two of which dropped
# 3.5-4.5 s later (docs/robust-grasp.md, "A watched pinch ends on its pads").
STEADY_EASE = 0.01
# Standard errors of the window's fitted slope the ease must clear as well: the pads' summed force
# scatters 0.003-0.006 N about its 1-s line (median per traced hold, up to 0.3 N where the lift shook
# it), one standard error 0.02 %/s, 0.3 %/s at worst ("A watched pinch says it holds on a steady slope").
STEADY_SIGMAS = 3.0
WATCH_BOUND = 2 * STEEP_WATCH  # s a pinch still easing is watched: held that long with the pads pressing, it holds


def position_command(values: np.ndarray) -> ControlData:
    return ControlData(hand=HandCommand(values=values, modes=(HandMode.POSITION,) * len(values)))


class Stillness:
    """How long each DOF has stood still. Still means it has not moved away from where it
    stopped by more than STILL_SPEED would take it in `window`: a finger pressed between
    the object and the table can shake in place (seen in PyBullet, 5 mrad at 50 Hz; in
    MuJoCo a Barrett finger pressed on the table), fast enough for its speed never to read
    zero."""

    def __init__(self, velocity_limit: np.ndarray, window: float) -> None:
        self.span = STILL_SPEED * velocity_limit * window

    def start(self, q: np.ndarray) -> None:
        self.anchor = q.copy()  # where each DOF was when it last moved
        self.seconds = np.zeros_like(q)

    def update(self, q: np.ndarray, dt: float) -> np.ndarray:
        moved = np.abs(q - self.anchor) > self.span
        self.anchor = np.where(moved, q, self.anchor)
        self.seconds = np.where(moved, 0.0, self.seconds + dt)
        return self.seconds


class PostureDrive(Controller):
    """Ramp every DOF's position reference to `goal` at `speed` times its speed limit.

    Done when every DOF is within 2 % of its range of the goal. If the fingers stop
    short of it for a second, something is in the way: the controller gives up, with an
    error unless `blocked_is_done`.
    """

    goal: np.ndarray
    blocked_is_done = False
    aim = "the posture"  # what the goal is, for the error of fingers blocked short of it

    def __init__(self, ctx: Context, speed: float = 1.0) -> None:
        super().__init__(ctx)
        hand = ctx.info.hand
        self.rate = speed * hand.velocity_limit
        self.tolerance = np.maximum(REACHED * (hand.upper - hand.lower), 1e-4)
        self.stillness = Stillness(hand.velocity_limit, STALL_TIME)

    def start(self, readings: Readings) -> None:
        self.reference = readings.hand_q.copy()
        self.stillness.start(readings.hand_q)

    def update(self, readings: Readings, dt: float) -> ControlData:
        step = self.rate * dt
        self.reference = self.reference + np.clip(self.goal - self.reference, -step, step)
        still = self.stillness.update(readings.hand_q, dt)
        if self.status is Status.RUNNING:
            short = self._short(readings.hand_q)
            if not short.any():
                self.finish(Status.DONE, "reached the hand posture")
            elif np.array_equal(self.reference, self.goal) and (still[short] >= STALL_TIME).all():
                where = ", ".join(f"{n} {q:.4g}" for n, q, s in zip(self.ctx.info.hand.dofs, readings.hand_q, short) if s)
                status = Status.DONE if self.blocked_is_done else Status.ERROR
                self.finish(status, f"fingers blocked short of {self.aim} ({where})")
        return position_command(self.reference)

    def _short(self, q: np.ndarray) -> np.ndarray:
        """Per DOF: not yet at the goal."""
        return np.abs(self.goal - q) > self.tolerance


class HoldPosition(PostureDrive):
    """Keep the fingers where they were when the state began (D5 2.2.4: hand idle).

    A finger pressing on something when the state begins keeps pressing with the effort
    it had: holding it at its measured position would take the grip off a grasped object.
    A self-locking drive (a Barrett's worm gear) keeps that effort by a force command; any
    other drive by its position servo, its reference set ahead of the finger by effort /
    stiffness, so that it also resists being pushed back. A bare force command has no such
    stiffness: lifting a cylinder pinched by the SDH2, whose distal joints held 0.23 N m,
    folded them open 0.15 rad in 0.17 s in PyBullet and the cylinder fell out.

    A pinch that may creep out (`STEEP_PINCH`: steeper than friction holds, or held by the
    object's flank) is watched: the hand says it holds such a grip only once it has held it
    STEEP_WATCH and the grip is steady, the pads' summed force not easing by more than
    STEADY_EASE per second over the last STEADY_WINDOW (the slope of their least-squares line,
    clear of its noise) and their contacts not moving across them, so that a lift which loses
    it meanwhile says so; a creeping object eases the pads as it goes. A grip still easing at
    WATCH_BOUND has been lifted and held that long: with the pads still pressing, it holds
    (docs/robust-grasp.md, "A steep pinch watched", "A pinch held by the flank", "A watched
    pinch ends on its pads", "A watched pinch says it holds on a steady slope").
    """

    def start(self, readings: Readings) -> None:
        super().start(readings)
        hand = self.ctx.info.hand
        loaded = (hand.closing * readings.hand_effort) > LOADED * hand.effort_limit
        self.forced = loaded & hand.self_locking
        preload = np.where(loaded & ~hand.self_locking, readings.hand_effort / hand.stiffness, 0.0)
        self.goal = readings.hand_q + preload
        self.effort = readings.hand_effort.copy()
        self.modes = tuple(HandMode.FORCE if forced else HandMode.POSITION for forced in self.forced)
        self.watch = STEEP_WATCH if self.ctx.memory.pop(STEEP_PINCH, False) else 0.0
        self.held = 0.0
        self.centres = PressureCentres(list(hand.pads))
        self.grip = RecentRows(2 + 2 * len(self.centres.names))  # time, the pads' summed force, their centres
        self._watched(readings)

    def _watched(self, readings: Readings) -> None:
        """Done once the grip has been held as long as it must be watched and is steady, or has
        been held to WATCH_BOUND, the pads pressing either way."""
        if not self.watch:
            self.finish(Status.DONE, "holding the fingers")
            return
        force = float(readings.pad_force.sum())
        self.grip.add(readings.time, np.concatenate(([readings.time, force], self.centres(readings).ravel())),
                      readings.time - STEADY_WINDOW)
        if self.held < self.watch or force <= 0.0:
            return  # watched too short, or nothing between the pads: the lift's grasp_lost tells that
        rows = self.grip.rows()
        eased, error = _ease(rows[:, 0], rows[:, 1])
        spread = np.fmax.reduce(rows[:, 2:], axis=0) - np.fmin.reduce(rows[:, 2:], axis=0)
        moved = np.nan_to_num(np.hypot(spread[0::2], spread[1::2]), nan=0.0)  # a pad pressing nothing is not read
        if eased + STEADY_SIGMAS * error <= STEADY_EASE * rows[:, 1].mean() and not (moved > SLIP_DISTANCE).any():
            self.finish(Status.DONE, f"holding the fingers, a pinch that may creep out watched {round(self.held, 1):g} s")
        elif self.held >= WATCH_BOUND - 1e-9:
            self.finish(Status.DONE, f"holding the fingers, a pinch that may creep out held {WATCH_BOUND:g} s, the pads "
                        f"easing {eased:.2g} N/s at {force:.2g} N, their contacts moved {1000 * moved.max(initial=0.0):.2g} mm")

    def update(self, readings: Readings, dt: float) -> ControlData:
        if self.status is Status.RUNNING:
            self.held += dt
            self._watched(readings)
        hand = self.ctx.info.hand
        locked = np.clip(self.effort + hand.stiffness * (self.goal - readings.hand_q), -hand.effort_limit, hand.effort_limit)
        values = np.where(self.forced, locked, self.goal)
        return ControlData(hand=HandCommand(values=values, modes=self.modes))


class HandShape(PostureDrive):
    """Drive the fingers to a named D5 hand shape (2.2.2) this hand can make.

    A grasp's preshape only opens the hand for the grasp that follows, which makes its own
    preshape: stopped against what a guarded approach met (a Barrett fingertip on the table
    when the approach comes down too low), it has done its part, so that is no error."""

    def __init__(self, ctx: Context) -> None:
        super().__init__(ctx, float(ctx.params["speed"]))
        shape = str(self.params["shape"])
        postures = ctx.info.hand.postures
        if shape not in postures:
            raise ValueError(f"the hand cannot make the shape '{shape}'; it makes: {', '.join(sorted(postures))}")
        self.goal = np.asarray(postures[shape], float)
        self.blocked_is_done = shape in PRESHAPES


class OpenTo(PostureDrive):
    """Open the hand to HAND_TARGET_POSITION: 0 = closed, 1 = fully open (thesis 3.3.4).

    Only the closing DOFs move, and only to open: a release lets go. A Barrett's spread or
    an SDH2's finger rotation stays as it is, since swinging the fingers round beside the
    object could knock it over; a closing DOF already at least as open as asked stays too.
    The SDH2's 'open' is not wider than its pinch at every joint: asked for 0.8 after
    placing a box, its distal joints closed to 0.61 rad onto it (2.6 N on each pad, the
    box lifted 6 mm), its proximal ones were pushed back past their goal, and the release
    waited out its timeout with the box in the fingers. Done once the encoders read every
    closing DOF at least as open as asked; fingers stopped short of it are an error
    saying where.
    """

    def __init__(self, ctx: Context) -> None:
        super().__init__(ctx, float(ctx.params["speed"]))

    def start(self, readings: Readings) -> None:
        super().start(readings)
        hand = self.ctx.info.hand
        opening = float(self.params["hand_position"])
        asked = hand.closed + opening * (hand.open - hand.closed)
        q = readings.hand_q
        self.closing = hand.closing
        self.goal = np.where((self.closing != 0) & (self.closing * (q - asked) > 0), asked, q)
        self.aim = f"the opening {opening:g}"

    def _short(self, q: np.ndarray) -> np.ndarray:
        """A closing DOF pushed open past its goal has reached it."""
        beyond = self.closing * (q - self.goal)  # > 0: more closed than the goal
        return np.where(self.closing != 0, beyond > self.tolerance, np.abs(self.goal - q) > self.tolerance)


def _ease(times: np.ndarray, forces: np.ndarray) -> tuple[float, float]:
    """How fast `forces` fall (N/s) along their least-squares line over `times`, and that slope's
    standard error from their scatter about the line: a whole window's trend, not two readings'
    difference, which one noisy reading can turn."""
    t = times - times.mean()
    spread = float(t @ t)
    if len(t) < 3 or spread <= 0.0:
        return 0.0, np.inf
    slope = float(t @ (forces - forces.mean())) / spread
    residual = forces - forces.mean() - slope * t
    return -slope, float(np.sqrt(residual @ residual / (len(t) - 2) / spread))
