"""What the arm and hand sides of one primitive tell each other (`Blackboard`, a fresh one
in `Context.blackboard` for each state), and the keys of `Context.memory`.

D5 2.2.4 runs an arm controller and a hand controller side by side in one state; some
primitives need them to coordinate (the robust grasp closes the fingers only once the
arm has found the object; a parallel gripper re-centres by asking the arm to move).
The executor runs the arm controller before the hand controller each tick, so a value
the hand writes is read by the arm one tick (5 ms) later, and the reverse in the same tick.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True, eq=False)
class Shift:
    """A move the hand asks the arm for: where the hand should close next, from where it is."""

    offset: np.ndarray  # (3,) m, hand frame
    turn: float = 0.0  # rad about the approach axis


@dataclass(eq=False)
class CapGrip:
    """What an unscrew's fingertips say of the cap, each tick (hand -> arm)."""

    pinched: bool = False  # every grasping pad has pressed the grasp force since this pinch's close
    empty: bool = False  # the pads closed nearer than FINGER_MIN_DISTANCE: nothing between them
    holding: bool = False  # every grasping pad touches something now
    axis: np.ndarray | None = None  # (3,) world: the pads' contacts' midpoint, averaged since the close
    drop: float = 0.0  # m under the pinch's start the arm holds the TCP: the pads' rise past the cap's believed width


@dataclass(eq=False)
class Blackboard:
    """The messages between the arm and hand sides of one state's primitive; each field
    says who writes it. A field left at its default is a message no controller sent."""

    contact: bool | None = None
    """Arm -> hand: True once the arm's approach has ended (object found, or nothing within
    reach): the hand may close. None: the arm does not say when (a gripper closes at once)."""

    preshaped: bool = True
    """Hand -> arm: False from the start of a grasp until the hand has opened into its preshape;
    the arm approaches only then (left True by a hand that does not preshape: the arm goes at
    once). Fingers still opening as the hand comes down at the approach velocity hit the
    object from above and knock it away (a ball pushed 11 cm aside by the Barrett, PyBullet)."""

    pressing: bool = False
    """Arm -> hand: True while the sliding grasp feels the closing fingers press on the surface
    it rides harder than it allows (Eq. 3.2 backing off): the fingers wait for the arm to rise.
    Also while the jaw grasp's arm rises to take off the support a press its closing jaws put on
    the wrist: the jaws say they hold the object only once it has, since a grip that slips out
    meanwhile must be looked for again, not waited out by a hand already done (the Panda's jaws
    held a speaker's top edge 1.5 s while the arm rose, then closed empty; both sides sat done
    until the task's timeout)."""

    fingers_stopped: bool = False
    """Hand -> arm: True once the fingers can close no further (object held, or limits)."""

    shift: Shift | None = None
    """Hand -> arm: a move for the arm to make before the hand tries again (finger-lost
    correction, D5's position and orientation corrections); the arm sets it back to None
    when done."""

    weigh: float | None = None
    """Hand -> arm: m for the arm to raise (+) or lower (-) the hand, holding, and then hold
    still there; the arm sets it back to None once it has, still for a moment. The robust
    grasp lifts what it holds off the table this way to feel where its weight hangs, and
    lowers its open hand back as far when the object slipped out of the pads meanwhile."""

    arm_nudge: np.ndarray | None = None
    """Hand -> arm: (3,) world-frame TCP velocity, m/s, to add to the arm's own motion."""

    jaws_empty: bool = False
    """Hand -> arm: True from the moment a gripper's jaws closed on nothing until they are
    open again, for an arm that looks for the object elsewhere."""

    jaws_brushed: float | None = None
    """Hand -> arm: with `jaws_empty`, where along the jaws' width (the hand's x, from -1 to 1
    of a pad's half width) the pads last felt something while they closed on nothing, or
    None: the object lies beyond that edge of the pads (pushed there by it)."""

    jaws_rim: float | None = None
    """Hand -> arm: with `jaws_empty`, the jaws reopen not from nothing but from a grip pressed
    partly through a finger's bare rim beside the pads: where along the jaws' width (the hand's
    x, from -1 to 1 of a pad's half width) the weaker pad felt the object at its edge (0 where
    it felt it further in, or cannot say). The arm moves along the jaws' width before they close again, not elsewhere."""

    cap: CapGrip | None = None
    """Hand -> arm: an unscrew's pinch on the cap, rewritten every tick; None before the first close."""

    release: bool = False
    """Arm -> hand: an unscrew's twist or pull is over: open into the preshape (the hand sets
    `preshaped` True once open), and close again on the next `contact`."""

    cap_off: bool = False
    """Arm -> hand: the unscrew pulled the pinched cap CAP_REMOVED_DISTANCE off: the hand keeps holding it, done."""


EMPTY_HAND = "empty_hand"
"""In `Context.memory`, not the blackboard: (3,) world-frame wrist force of the empty hand,
N, as the latest grasp began, or as an arm that searches for the object last began a
descent, in free air; the load a hand carries beyond it is what it holds."""

HAND_LEVEL = "hand_level"
"""In `Context.memory`: (3, 3) the top-down hand a move's `tilt` last turned from (its
`<pose>`'s identity). A move that starts with the hand's x axis nearer vertical than level,
or its approach axis nearer level than down, turns from it again: the top-down hand derived
from a hand turned to the side has a yaw its sideways x axis does not say, and a Melfa side
approach's second move rolled the jaws 90 degrees to close up and down, a finger cutting
into the object's side (issue 32); a Barrett rolled to pinch across a bottle, its x axis
level, rolled back 40 degrees on the way down to it."""

YAW_REFERENCE = "yaw_reference"
"""In `Context.memory`: the yaw (rad, world) of the hand's x when a move first turned it to a
given `yaw`; later turns keep the hand within WIND_LIMIT of it (primitives/arm/motion.py)."""

AIMED = "aimed"
"""In `Context.memory`: the points (each (3,), world) every vision round of the run chose to
approach, in order. The run's, not one arm's: a cluster still seen near one was missed."""

ARM_TWIST = "arm_twist"
"""In `Context.memory`: (6,) the TCP twist the arm was last commanded (world frame, m/s and
rad/s), kept by the executor. A motion that takes the arm over ramps from it: one that
started from rest stopped a lifting SDH2 within a tick, and its wrist read the 10-15 N of
that stop as a contact."""

LOCATED_ALONG = "located_along"
"""In `Context.memory`: whether the latest jaw grasp of a robot with a range sensor saw where
along its jaws' width the object's top spans, and closed on its middle (True), or closed not
knowing (False); absent where no such grasp ran. A place that cannot weigh where the object
hangs holds it where the hand shape says only if it was."""

SHORT_OF_TARGET = "short_of_target"
"""In `Context.memory`: (3,) world vector, m, from where the latest guarded move stopped on a
contact to the target it was going to; absent once a move arrived. A gripper's unscrew reads
it: its jaws, lowered around a cap, stopped short where one landed on the cap's top."""

STEEP_PINCH = "steep_pinch"
"""In `Context.memory`: True where the latest robust grasp held a pinch that may creep out:
narrower than its object's believed least width by more than friction allows (gap < W /
hypot(1, mu)), or with the object's weight hanging beyond the pads' edge; on a round body
its pads press faces turned from the squeeze and squeeze it out, slowly. The hand that holds
it next reads it once (`HoldPosition`) and watches the grip before it says it holds."""

ARM_KEYS = frozenset({EMPTY_HAND, ARM_TWIST, HAND_LEVEL, YAW_REFERENCE, SHORT_OF_TARGET, STEEP_PINCH})
"""The keys of `Context.memory` that say something of one arm: in a run of two arms each
keeps its own (atd.runtime.values.ArmMemory); every other key, a named value, is the run's."""
