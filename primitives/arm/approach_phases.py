"""The phases of the grasps' arm sides and what each remembers while it lasts: the robust
grasp's (docs/robust-grasp.md draws the machine) and the naive baseline's. Both approach
the object the same way (`Approaching`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum

import numpy as np

from primitives.arm.motion import Stall
from primitives.robot import Readings

APPROACH_ACCELERATION = 0.3  # m/s^2 an approach speeds up at: a sudden start reads on the wrist as a contact
SETTLE = 0.1  # s still, once level or over a contact, before the wrist's reading is taken as the free hand's


class Phase(Enum):
    """Where the robust grasp's arm is. A tick runs the phases' methods in this order; a
    phase entered earlier in the tick runs at once, one entered from a later phase waits
    for the next tick."""

    APPROACH = "approach"  # along the grasp direction until a contact, aligning on it (Eq. 3.1)
    SLIDE = "slide"  # riding the supporting surface while the fingers close (Eq. 3.2)
    HOLD = "hold"  # the fingers have closed: stay, and raise or lower the hand when asked
    SETTLE = "settle"  # turning level, or stopped after a move: still before the wrist is read afresh
    ACROSS = "across"  # off a contact on the object's top to over it, or in from a known wall first
    SHIFT = "shift"  # making a move the hand asked for


@dataclass
class Approaching:
    """An approach, from where it (re)started."""

    origin: np.ndarray  # world TCP position it started from: MAX_DISTANCE is counted from there
    speed: float = 0.0  # m/s, rising to the approach velocity
    stall: Stall = field(default_factory=Stall)  # no further along it for a while: something the arm cannot pass

    def travelled(self, readings: Readings, direction: np.ndarray) -> float:
        """m covered along the grasp direction (hand frame) since the approach (re)started."""
        return float((readings.tcp[:3, 3] - self.origin) @ (readings.tcp[:3, :3] @ direction))

    def velocity(self, direction: np.ndarray, top_speed: float, dt: float) -> np.ndarray:
        """One tick's velocity along the grasp direction (hand frame), speeding up at
        APPROACH_ACCELERATION to `top_speed`."""
        self.speed = min(top_speed, self.speed + APPROACH_ACCELERATION * dt)
        return self.speed * direction


@dataclass
class Holding:
    """The place the arm holds once the fingers have closed."""

    goal: np.ndarray  # world TCP position; a raise or lower the hand asks for moves it


@dataclass
class Shifting:
    """A move the hand asked for."""

    goal: np.ndarray  # world TCP position
    probing: bool  # along the approach: looking for the object, so a contact ends it
    started: float  # s: when the move began


class NaivePhase(Enum):
    """Where the naive grasp's arm is (thesis 3.4.1); the value is the method that runs a tick of it."""

    PREGRASP = "_pregrasp"  # back along the grasp direction to the pregrasp pose, `distance` from the grasp pose
    SETTLE = "_settle"  # still at the pregrasp pose, the hand preshaped, before the wrist is read afresh
    APPROACH = "_approach"  # forward until a contact or `distance` (back at the grasp pose the task planned)
    HOLD = "_hold"  # stopped: stay while the hand closes
