"""Where the object to slide truly stands, from two of its edges seen by a range sensor
looking along the approach axis (Baxter's IR): the task's pose is belief, and an object that
stands 2 cm from it ends 2 cm from its target however well it is carried.

The beam is swept outward from over the object, along the believed centre line, across its
trailing edge (behind it on the slide's way) and across the edge to the side of the way; where
the beam drops off the top, the edge is. Each edge found moves the object's believed centre
along the sweep by as much as the edge stands from where the believed pose puts it. After
the drag, the trailing edge's sweep moved along the way says whether the object came along.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from atd.model.task import ObjectInfo
from atd.model.vocabulary import ObjectClass

# m inside a believed edge a sweep starts (how far the task's pose may be off); twice this without a drop: no edge
INSET = 0.03


@dataclass(frozen=True)
class Sweep:
    """One look across an edge: the beam starts over `start` and moves along `outward`
    (unit, tangential); the believed edge stands `edge` m from the believed `centre` along it."""

    centre: np.ndarray
    start: np.ndarray
    outward: np.ndarray
    edge: float


def sweeps(obj: ObjectInfo, normal: np.ndarray, direction: np.ndarray) -> tuple[Sweep, Sweep]:
    """The sweeps across the trailing edge and the side edge, for a slide along `direction`
    (unit, tangential) on a surface of normal `normal`."""
    pose = obj.pose.as_array()
    centre = pose[:3, 3]
    found = []
    for outward in (-direction, np.cross(normal, direction)):
        edge = _edge_distance(obj, pose[:3, :3], outward)
        found.append(Sweep(centre, centre + (edge - INSET) * outward, outward, edge))
    return found[0], found[1]


def moved(sweep: Sweep, by: np.ndarray) -> Sweep:
    """The same look, for the object moved `by` (m, world)."""
    return replace(sweep, centre=sweep.centre + by, start=sweep.start + by)


def _edge_distance(obj: ObjectInfo, rotation: np.ndarray, outward: np.ndarray) -> float:
    """m from the believed centre to where a line along `outward` leaves the believed
    footprint: the nearest of a box's faces across it, a round object's radius."""
    size = obj.effective_size
    if (obj.object_class or ObjectClass.BOX) is not ObjectClass.BOX:
        return float(size[0])
    along = np.abs(rotation[:, :2].T @ outward)
    half = np.array(size[:2]) / 2
    return float(np.min(half[along > 1e-9] / along[along > 1e-9]))


def shift(found: tuple[Sweep, ...], edges: list[float]) -> np.ndarray:
    """How far the object stands from its believed pose: each edge's offset (m from the
    believed centre along its sweep, as seen) from where the belief puts it, along the sweep
    (the two sweeps are square to each other)."""
    return sum(((seen - sweep.edge) * sweep.outward for sweep, seen in zip(found, edges)), np.zeros(3))
