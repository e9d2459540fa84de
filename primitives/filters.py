"""Signal conditioning shared by controllers and conditions: taring, low-pass, debounce.

A wrist sensor reads the hand's own weight, and whatever it holds, all the time; a
threshold on the raw reading would fire at rest. Controllers and conditions therefore
look at the *contact* wrench: the reading minus what it was when the state began, with
the weight turned with the hand so that a rotating wrist does not look like a contact.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass

import numpy as np

from atd.model.frames import GRAVITY
from primitives.robot import HandInfo, PadInfo, Readings


class LowPass:
    """First-order low-pass with time constant `tau` (0 = pass through)."""

    def __init__(self, tau: float) -> None:
        self.tau = tau
        self.value: np.ndarray | None = None

    def reset(self, value: np.ndarray) -> None:
        self.value = np.array(value, float)

    def __call__(self, x: np.ndarray, dt: float) -> np.ndarray:
        if self.value is None or self.tau <= 0.0:
            self.value = np.array(x, float)
        else:
            self.value += (1.0 - math.exp(-dt / self.tau)) * (x - self.value)
        return self.value


def world_load(readings: Readings) -> np.ndarray:
    """The force on the wrist in the world frame: a load's weight reads the same there
    however the hand is turned."""
    return readings.tcp[:3, :3] @ readings.wrench[:3]


WEIGHED = 0.5  # of a held object's believed weight the wrist must feel to say where it hangs: less, the table has it


def held_wrench(hand: HandInfo, readings: Readings) -> np.ndarray:
    """The wrist reading less the empty hand's own weight at its present posture (from the
    hand's model): what it holds or touches, in the hand frame about the sensor. Unlike
    `ContactWrench` it needs no reading of the empty hand, so it serves once the hand
    holds something whose weight nobody tared."""
    weight = readings.tcp[:3, :3].T @ np.array([0.0, 0.0, -GRAVITY * hand.mass])
    own = np.concatenate((weight, np.cross(hand.centre_of_mass(readings.hand_q) - hand.wrist, weight)))
    return readings.wrench - own


RING_RATE = 1200.0  # N/s between ticks: faster is a knock still ringing, slower the arm's own motion or a lift (docs/unscrew-campaign.md)
STILL_TIME = 0.05  # s without such a jump before the tare is held: a put-down's ring dies within 0.04 s
TARE_LIMIT = 0.5  # s: held by then whatever it reads, a hand still knocked about is pressed on, not ringing


@dataclass(frozen=True, eq=False)
class Leaving:
    """A motion that may start pressed on something it moves away from, whichever way the
    press lies (free_one's rise pushed up off an object, or held down by one over a finger;
    a free move off fingers blocked on what they let go), by a hand of the believed model
    `hand`, feeling contacts of `threshold` N; `rises`: the motion only goes up."""

    hand: HandInfo
    threshold: float
    rises: bool = False

    def beyond(self, readings: Readings) -> np.ndarray:
        """The force on the wrist beyond the believed empty hand, world frame."""
        return readings.tcp[:3, :3] @ held_wrench(self.hand, readings)[:3]

    def press(self, readings: Readings) -> tuple[float, np.ndarray]:
        """N with which something the hand leaves behind pushes it, and the way it pushes
        (world, unit), where that alone could read as a contact once eased (at least
        `threshold`); else 0 N. Unless the motion rises, a downward part is left out: a held
        object's weight eases as it is set down, a contact to feel."""
        beyond = self.beyond(readings)
        if not self.rises:
            beyond[2] = max(float(beyond[2]), 0.0)
        pushed = math.sqrt(float(beyond @ beyond))
        along = beyond / pushed if pushed > 0.0 else beyond
        return (pushed if pushed >= self.threshold else 0.0), along


class ContactWrench:
    """The wrench that contacts add since `start`: tared, gravity turned with the hand, filtered.

    At `start` the reading is taken to be pure load (hand plus held object). Its force is
    a fixed vector in the world, so at a later hand rotation R it reads R^T R0 f0 in the
    hand frame; what is left over is contact. Torques are tared in the hand frame only
    (the load's centre of mass is not known), which is exact as long as the hand keeps
    its orientation, as every primitive here does while it watches for contact.

    A state that begins as the last one's knock still rings (a put-down stopped on the
    table) would tare on a passing reading and take its settling for a contact; so while
    the force jumps faster than RING_RATE the tare follows the reading, and it is held
    once the reading has not jumped for STILL_TIME (or TARE_LIMIT after the start). A start
    whose reading does not jump keeps the start's reading, as before.

    A motion that starts pressed on what it moves away from (`Leaving`: an explore rising
    off an object the last state pressed on at 200 N, or held down under one, a free move
    off fingers blocked on what they let go) feels that press ease as it goes, and against
    the start's tare the easing reads as a force against the motion, the same as a new
    contact. So while such a press eases the tare eases with it, along the way it pushed,
    down to what the believed empty hand would read, and never back; a contact the motion
    then meets reads in full.
    """

    def __init__(self, filter_time: float = 0.0, leaving: Leaving | None = None) -> None:
        self._filter = LowPass(filter_time)
        self._leaving = leaving
        self._press = 0.0  # N that pressed the hand at the tare, along `_along`
        self._along = np.zeros(3)  # the way that press pushed, world frame
        self._eased = 0.0  # N of it eased so far: a press that let go does not come back
        self._load_world = np.zeros(3)
        self._torque0 = np.zeros(3)
        self.value = np.zeros(6)
        self._started = 0.0
        self._last = np.zeros(3)  # the force read last tick, hand frame
        self._settling = False  # the tare may still follow a ringing reading
        self._rang: float | None = None  # when the reading last jumped; None: not since the start

    def start(self, readings: Readings, settle: bool = True) -> None:
        """Tare on this reading; `settle` False holds it at once, for a tare taken in the
        middle of a primitive's own work, where a jump is its doing, not a ring (the
        unscrew's twist and pull: the Melfa's wrist jumped 9-11 N in a tick as it worked
        the jam jar's cap)."""
        self._started = readings.time
        self._tare(readings)
        self._settling, self._rang = settle, None

    def _tare(self, readings: Readings) -> None:
        self._load_world = world_load(readings)
        if self._leaving is not None:
            self._press, self._along = self._leaving.press(readings)
            self._eased = 0.0
        self._torque0 = readings.wrench[3:].copy()
        self._filter.reset(np.zeros(6))
        self.value = np.zeros(6)
        self._last = readings.wrench[:3].copy()

    def update(self, readings: Readings, dt: float) -> np.ndarray:
        raw = readings.wrench
        if self._settling:
            self._settle(readings, dt)
        load = self._load_world if self._press == 0.0 else self._eased_load(readings)
        force = raw[:3] - readings.tcp[:3, :3].T.dot(load)  # .dot: half the cost of @ here
        self.value = self._filter(np.concatenate((force, raw[3:] - self._torque0)), dt)
        return self.value

    def _eased_load(self, readings: Readings) -> np.ndarray:
        """The start's load less as much of its press as has eased since, along the way it
        pushed; once eased it stays so, and a push that way later is a contact (a finger
        hooked under a rim again as the rise goes on)."""
        leaving = self._leaving
        assert leaving is not None
        pressing = float(leaving.beyond(readings) @ self._along)
        self._eased = min(max(self._eased, self._press - pressing), self._press)
        return self._load_world - self._eased * self._along

    def _settle(self, readings: Readings, dt: float) -> None:
        """Follow the reading while it rings; hold the tare once it is still."""
        now, force = readings.time, readings.wrench[:3]
        step = force - self._last
        self._last = force.copy()
        if math.sqrt(float(step.dot(step))) > RING_RATE * dt:
            self._rang = now
        quiet = now - (self._started if self._rang is None else self._rang)
        if quiet >= STILL_TIME or now - self._started >= TARE_LIMIT:
            self._settling = False
        elif self._rang is not None:
            self._tare(readings)

    @property
    def force(self) -> float:
        """||F|| of the contact force, N."""
        x, y, z = self.value[:3].tolist()  # plain floats: numpy's scalars cost more per operation
        return math.sqrt(x * x + y * y + z * z)


def contact_across(wrench: np.ndarray, depth: float) -> np.ndarray | None:
    """(x, y, 0) in the sensor's axes: where a contact's force, acting along its line of
    action (from the force and the torque about the sensor), crosses the plane `depth`
    beyond the sensor along its z axis; None for a force with nothing along z."""
    force, torque = wrench[:3], wrench[3:]
    f2 = float(force.dot(force))
    if f2 < 1e-12 or abs(float(force[2])) < 1e-6:
        return None
    closest = np.cross(force, torque) / f2  # the line's point nearest the sensor
    point = closest + (depth - float(closest[2])) / float(force[2]) * force
    return np.array([point[0], point[1], 0.0])


class Debounce:
    """True once its input has been true for `for_time` without a break (0 = at once)."""

    def __init__(self, for_time: float) -> None:
        self.for_time = for_time
        self.held = -1.0  # s the input has been true; -1 = it is false

    def reset(self) -> None:
        self.held = -1.0

    def __call__(self, value: bool, dt: float) -> bool:
        self.held = (self.held + dt if self.held >= 0.0 else 0.0) if value else -1.0
        return self.held >= self.for_time - 1e-9


class RecentRows:
    """The rows of the last stretch of time, as one array: a window kept in a buffer that is
    compacted now and then, rather than an array rebuilt from a list of rows every tick (a
    0.1 s window at 200 Hz took 20 rows' copying a tick)."""

    def __init__(self, width: int, capacity: int = 64) -> None:
        self._buffer = np.empty((capacity, width))
        self._times: deque[float] = deque()
        self._end = 0  # the row after the newest

    def clear(self) -> None:
        self._times.clear()
        self._end = 0

    def add(self, time: float, row: np.ndarray, since: float) -> None:
        """Keep `row` taken at `time`; forget the rows taken before `since`."""
        self._times.append(time)
        while self._times[0] < since:
            self._times.popleft()
        kept = len(self._times) - 1  # those before this row
        if self._end == len(self._buffer):
            grown = np.empty((max(len(self._buffer), 2 * kept + 2), self._buffer.shape[1]))
            grown[:kept] = self._buffer[self._end - kept:self._end]
            self._buffer, self._end = grown, kept
        self._buffer[self._end] = row
        self._end += 1

    def rows(self) -> np.ndarray:
        """The rows kept, oldest first (a view, valid until the next `add`)."""
        return self._buffer[self._end - len(self._times):self._end]


class PressureCentres:
    """Each taxel pad's centre of pressure (the taxel image's force-weighted cell centre, m,
    in the pad's frame, x along its columns): where its contacts lie, NaN on a pad pressing
    nothing. Pads without a taxel array are not read."""

    def __init__(self, pads: list[PadInfo]) -> None:
        arrays = [p for p in pads if p.taxels is not None]
        self.names = [p.name for p in arrays]
        self.cells = [self._centres(p.taxels, p.half_size) for p in arrays]

    @staticmethod
    def _centres(taxels: tuple[int, int], half: tuple[float, float]) -> tuple[np.ndarray, np.ndarray]:
        rows, cols = taxels
        x = ((np.arange(cols) + 0.5) / cols * 2.0 - 1.0) * half[0]
        y = ((np.arange(rows) + 0.5) / rows * 2.0 - 1.0) * half[1]
        return x, y

    def __call__(self, readings: Readings) -> np.ndarray:
        """(pads, 2): each pad's centre now."""
        centres = np.full((len(self.names), 2), np.nan)
        for i, (name, (x, y)) in enumerate(zip(self.names, self.cells)):
            image = readings.taxels[name]
            total = float(image.sum())
            if total > 0.0:
                centres[i] = np.array([image.sum(axis=0) @ x, image.sum(axis=1) @ y]) / total
        return centres
