"""The values one state leaves in `Context.memory` for later states to read (thesis 3.4.3:
perceive an object, then grasp it where it was found).

A perceptual primitive writes one of these under the name its state gives (`writes`); a
condition or a later controller reads it back by that name. Typed, so a reader knows what it
holds without guessing at dictionary keys, and frozen, so no reader changes what another reads.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Contact:
    """Where an `explore` move felt something: the position (world frame) of the point of the
    hand that touched when it did (the TCP where its state names no hand shape),
    which sensor felt it ("wrist", or the pad's name), how hard (N), and the direction the
    hand was moving in (a unit world vector). An ATD `point` value."""

    point: np.ndarray  # (3,)
    sensor: str
    force: float
    direction: np.ndarray  # (3,)
    time: float  # s of simulated time


@dataclass(frozen=True)
class Approach:
    """Where to grasp next (thesis 3.4.3's approach vector): `pose` is a top-down TCP pose
    (4x4, world) above the object, clear of the container's rim, for the grasp to descend
    from; `point` the highest place known to be on the object (world; for random blind, the
    container's floor under the pose). `method` says which generator found it,
    `candidates` how many objects it saw (None: it cannot count) and `top` the height (world
    z) of the top it saw under the pose (None: it does not know it), which a grasp's
    `<object_top from>` reads; `either_way` whether the hand grasps alike turned half a turn
    from the pose (parallel jaws), so a move may turn it the shorter way. An ATD `pose` value."""

    pose: np.ndarray  # (4, 4)
    point: np.ndarray  # (3,)
    method: str
    candidates: int | None = None
    top: float | None = None
    either_way: bool = True


@dataclass(frozen=True)
class NothingFound:
    """A perceptual primitive looked and found no object; `reason` says where it looked."""

    method: str
    reason: str


Found = Approach | NothingFound
"""What a `perceive` state writes under its name."""
