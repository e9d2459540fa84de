"""A screw cap on a bottle or jar (thesis 3.4.2): what the engines build and what a judge reads.

A threaded object is one `Body` (its `size` and `pose` are the whole object's: the box or
cylinder around bottle and cap, so resting, dropping and the robot's belief treat it as
any other object) with a `Thread`: a main part, a neck on top of it, and the cap sitting
on the neck. On the thread the cap turns and rises on the neck, the rise tied to the turn
(pitch per turn), the turn resisted by a dry friction torque: in MuJoCo the cap is a free
body welded to a "nut" that does so, in PyBullet it is the object's link that does. At the
thread's end the weld is let go (MuJoCo) or the cap goes on as a free body with the link's
pose and velocity (PyBullet): from then on only contacts hold it, so it is lifted off,
dropped or left on the neck by the physics alone.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

#: Between the cap's underside and the neck's rim when closed: the thread, not a contact,
#: holds a closed cap, so turning it meets only the thread's friction.
SEAT_GAP = 0.0005  # m
#: A free cap whose underside is this close to the neck's rim (and over it) rests on the bottle;
#: one this close to the table top rests on the table.
RESTING = 0.005  # m
#: Turns short of the thread's end that count as its end: the nut stops at its limit there.
END_SLACK = 1e-3  # turns
#: Clearance between a fixture's jaws and the object they hold (the weld holds it, the jaws show where).
JAW_GAP = 0.001  # m
JAW_THICKNESS = 0.01  # m
Rest = Literal["bottle", "table", "held", "elsewhere"]


@dataclass(frozen=True)
class Thread:
    """The cap and the thread of a threaded object. Heights are along the object's z axis,
    lengths in m, the cap's mass in kg (part of the object's), `torque` in N m. `fixture`:
    the object stands in a clamp fixed to the table (for one-arm robots)."""

    neck_radius: float
    neck_height: float
    cap_radius: float
    cap_height: float
    cap_mass: float
    pitch: float  # m the cap rises per turn
    turns: float  # from closed until it comes free
    torque: float  # the thread's friction torque, N m
    fixture: bool = False

    @property
    def travel(self) -> float:
        """How far the cap rises along the thread before it comes free, m."""
        return self.pitch * self.turns

    @property
    def end_angle(self) -> float:
        """The turn (rad, unscrewing positive) at which the cap comes free."""
        return 2 * math.pi * self.turns

    def main_height(self, height: float) -> float:
        """Of an object `height` tall, the main part's height (below the neck)."""
        return height - self.neck_height - self.cap_height - SEAT_GAP

    def parts(self, height: float) -> tuple[float, float, float]:
        """Centres along z, in the object's frame, of the main part, the neck and the closed cap."""
        main = self.main_height(height)
        return -height / 2 + main / 2, -height / 2 + main + self.neck_height / 2, height / 2 - self.cap_height / 2

    def closed_cap(self, pose: np.ndarray, height: float) -> np.ndarray:
        """Where the closed cap stands (4x4, its centre) on an object `height` tall at `pose`."""
        local = np.eye(4)
        local[2, 3] = self.parts(height)[2]
        return pose @ local

    def cap_inertia(self) -> tuple[float, float, float]:
        r, h, m = self.cap_radius, self.cap_height, self.cap_mass
        side = m * (3 * r * r + h * h) / 12
        return (side, side, m * r * r / 2)

    def neck_top(self, height: float) -> float:
        """The neck's rim, z in the object's frame."""
        return self.parts(height)[1] + self.neck_height / 2


def jaws(pose: np.ndarray, footprint: tuple[float, float], height: float) -> list[tuple[np.ndarray, tuple]]:
    """A fixture's four jaws around an object standing at `pose` with `footprint` (x, y full
    widths) and `height`: (4x4 pose, box size) each, a third of the object's height tall, on the table."""
    tall = height / 3
    found = []
    for axis in (0, 1):
        for sign in (1.0, -1.0):
            local = np.eye(4)
            offset = footprint[axis] / 2 + JAW_GAP + JAW_THICKNESS / 2
            local[axis, 3] = sign * offset
            local[2, 3] = -height / 2 + tall / 2
            size = [0.0, 0.0, tall]
            size[axis] = JAW_THICKNESS
            size[1 - axis] = footprint[1 - axis] + 2 * (JAW_GAP + JAW_THICKNESS)
            found.append((pose @ local, tuple(size)))
    return found


@dataclass(frozen=True)
class CapState:
    """The simulator's truth about one cap, for judges (never for controllers): how far it
    has been turned open (rad), whether it is off the thread, its 4x4 pose, and where it rests."""

    turned: float
    free: bool
    pose: np.ndarray
    rests: Rest

    @property
    def turns(self) -> float:
        """How far it was turned open, in turns."""
        return self.turned / (2 * math.pi)


def resting_place(thread: Thread, height: float, bottle: np.ndarray, cap: np.ndarray, free: bool,
                  touches_robot: bool) -> Rest:
    """Where a cap at pose `cap` rests: on its bottle while threaded; once free, held by the
    robot (touching it: a cap pinched just over the neck is held, not left on the bottle), on
    its bottle (its underside on the neck's rim, its centre over the neck), on the table (its
    lowest point near the table top), or elsewhere (on another object, falling)."""
    if not free:
        return "bottle"
    if touches_robot:
        return "held"
    local = np.linalg.solve(bottle, cap)
    underside = local[2, 3] - thread.cap_height / 2
    over_neck = math.hypot(local[0, 3], local[1, 3]) <= thread.neck_radius
    if over_neck and abs(underside - thread.neck_top(height)) <= RESTING:
        return "bottle"
    # Lowest point of a cylinder turned any way: its centre minus the reach of its rim and ends along z.
    axis_z = abs(cap[2, 2])
    lowest = cap[2, 3] - thread.cap_radius * math.sqrt(max(0.0, 1 - axis_z * axis_z)) - thread.cap_height / 2 * axis_z
    return "table" if lowest <= RESTING else "elsewhere"
