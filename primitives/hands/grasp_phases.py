"""The phases of a multi-finger grasp's hand side and what each remembers while it lasts.

A grasp is always in one `Phase`; each names the method of `FingerGrasp` (or of the
robust grasp) that runs its tick, so the machine reads from the enum and its transitions
from those methods (docs/robust-grasp.md draws it).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum

import numpy as np

from primitives.blackboard import Shift
from primitives.filters import LowPass


class Phase(Enum):
    """Where the hand side of a multi-finger grasp is; the value is the method that runs a tick of it."""

    PRESHAPE = "_preshape"  # opening into the preshape; the arm waits for it
    FREE = "_free"  # the arm rises so that a preshape blocked on the table is made in free air
    WAIT = "_wait"  # preshaped: the arm approaches until it says the hand may close
    CLOSE = "_close"  # the grasping fingers close until they can close no further
    REOPEN = "_reopen"  # a close failed: back to the preshape before the arm moves the hand
    SHIFT = "_shift"  # open, while the arm makes the correction's move
    HOLD = "_hold"  # closed on the object: force adaptation until the pads settle
    WEIGH = "_weigh"  # holding, lifted off the table by the arm: where does the weight hang
    SET_DOWN = "_set_down"  # holding, lowered back by the arm before grasping across the weight
    FAILED = "_failed"  # ended in an error; the fingers stay where they are

    @property
    def holding(self) -> bool:
        """The fingers press on the object by force (the other phases command positions)."""
        return self in (Phase.HOLD, Phase.WEIGH, Phase.SET_DOWN)


@dataclass
class Closing:
    """What one close of the robust grasp has felt on its way, for judging how it ended."""

    brushed: set[str] = field(default_factory=set)  # fingers whose pads touched something on the way
    felt_by: set[str] = field(default_factory=set)  # fingers whose pads felt something above the table
    felt_at: float = 0.0  # m across the pinch line where the pads last felt the object
    pinched: float = 0.0  # s every grasping pad has pressed with PINCHED times the grasp force
    looked: float = -np.inf  # s: when the pads' gap was last looked at


@dataclass
class Holding:
    """Force adaptation's state while the fingers hold the object."""

    felt: LowPass  # the pad forces, averaged before the hold is judged
    holding: float = 0.0  # s since the hold began
    settled: float = 0.0  # s the squeeze has stayed in the band about the grasp force
    entered: float = np.inf  # N: the squeeze when it last came into the band
    lost_for: float = 0.0  # s a grasping pad has felt nothing while another presses
    short: bool = False  # settled below the grasp force, every finger at its effort limit


@dataclass
class Weighing:
    """The held object lifted to feel where its weight hangs, and what to do once it is set down."""

    weights: list[np.ndarray] = field(default_factory=list)  # wrist loads felt, lifted, less the hand's own
    regrasp: np.ndarray = field(default_factory=lambda: np.zeros(3))  # the shift across its weight (hand frame)
    off_line: str = ""  # why, for the error once the corrections are spent


@dataclass
class Corrections:
    """What the robust grasp's corrections remember from one close to the next."""

    retries: int = 0  # corrections made so far, of RETRIES
    shift: Shift | None = None  # the move the arm is to make before the next close
    lost_shift: np.ndarray = field(default_factory=lambda: np.zeros(3))  # the latest finger-lost shift
    quality: float = np.inf  # D5's Q at the latest uneven grasp
    freed: bool = False  # the arm has risen once to free a blocked preshape
    lifted: bool = False  # the arm has risen once off the table the fingertips were told to close on
    jammed: bool = False  # the latest close stopped on something beside the pads
    raised: np.ndarray = field(default_factory=lambda: np.zeros(3))  # hand frame: a raise to weigh what dropped
    weighed_off: float = 0.0  # m across the pinch line (signed) the weight hung at the latest weighing
