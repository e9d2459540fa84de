"""The phases of the unscrew's arm side and what each remembers while it lasts
(docs/writing-a-primitive.md draws the machine, thesis Fig. 3.11)."""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum

import numpy as np

from primitives.arm.jaw_grasp import STALL_TIME
from primitives.arm.motion import Stall


class Phase(Enum):
    """Where the unscrew's arm is; the value is the method of `UnscrewArm` that runs a tick of it."""

    SEAT = "_seat"  # a gripper's open jaws down to where the guarded descent was going, feeling for a jaw on the cap
    ACROSS = "_across"  # off the cap's top and across by the jaws' room around the cap, towards the jaw that was on it
    PINCH = "_pinch"  # still at the start pose while the fingers close on the cap
    TWIST = "_twist"  # turning the pinched cap TWIST_ANGLE about the approach axis, through the grasp centre
    PULL = "_pull"  # backing off along the approach: does the cap come, or does its thread hold it?
    RELEASE = "_release"  # still, while the fingers open off the cap
    RETURN = "_return"  # back to the start pose, moved onto the cap's axis by the alignment, to pinch again
    OFF = "_off"  # the cap came off: holding it where the pull ended
    FAILED = "_failed"  # gave up: holding still


@dataclass
class TcpPose:
    """A pose the arm goes to or holds: the start of every pinch (the reactive alignment
    moves it), or where a still phase began."""

    position: np.ndarray  # world TCP
    rotation: np.ndarray  # world TCP orientation


@dataclass
class Seating:
    """The jaws' way down around the cap: where they go, and how they got off its top."""

    first: np.ndarray  # world TCP the guarded descent was going to
    goal: np.ndarray  # where this descent goes: `first`, or moved across it by the search
    route: list[np.ndarray] = field(default_factory=list)  # world TCP waypoints off the cap's top and across
    stall: Stall = field(default_factory=lambda: Stall(STALL_TIME))  # the descent pressing on something
    watched: bool = False  # off the top: the move across watches the wrist for a jaw meeting the cap


@dataclass
class Twisting:
    """One twist."""

    goal: np.ndarray  # world TCP orientation once turned TWIST_ANGLE
    centre: np.ndarray  # world: the grasp centre, held where it was pinched unless the arm gives way (`_give_way`)
    started: float  # s: when it began
    yielded: float = 0.0  # m the arm has given way along the jaws' line to a jaw the twist drives into the cap


@dataclass
class Pulling:
    """One pull."""

    origin: np.ndarray  # world TCP position it started from
    rotation: np.ndarray  # world TCP orientation it keeps (the twist's)


@dataclass
class Tally:
    """What the whole unscrew has done so far, for its verdict and the trace."""

    pinches: int = 0  # pinches begun, of MAX_PINCHES
    twists: int = 0  # twist moves begun (thesis Table 3.4 "Moves")
    aligned: int = 0  # times the alignment moved the start pose
    seated: int = 0  # moves across a gripper's jaws made off the cap's top before the first pinch (search points)
    ended: str = ""  # why the latest twist or pull ended early
