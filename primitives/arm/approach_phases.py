"""The phases of the robust grasp's arm side and what each remembers while it lasts
(docs/robust-grasp.md draws the machine)."""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

import numpy as np


class Phase(Enum):
    """Where the robust grasp's arm is. A tick runs the phases' methods in this order; a
    phase entered earlier in the tick runs at once, one entered from a later phase waits
    for the next tick."""

    APPROACH = "approach"  # along the grasp direction until a contact, aligning on it (Eq. 3.1)
    SLIDE = "slide"  # riding the supporting surface while the fingers close (Eq. 3.2)
    HOLD = "hold"  # the fingers have closed: stay, and raise or lower the hand when asked
    SETTLE = "settle"  # turning level, or stopped after a move: still before the wrist is read afresh
    ACROSS = "across"  # rising off a contact on the object's top and moving the grasp centre over it
    SHIFT = "shift"  # making a move the hand asked for


@dataclass
class Approaching:
    """An approach, from where it (re)started."""

    origin: np.ndarray  # world TCP position it started from: MAX_DISTANCE is counted from there
    speed: float = 0.0  # m/s, rising to the approach velocity
    best: float | None = None  # m: the furthest it has got along the approach
    best_at: float = 0.0  # s: when it got there


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

