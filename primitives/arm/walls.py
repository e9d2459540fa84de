"""The walls a grasp keeps inside: the containers the task knows (belief, the ATD's
<container>, never the simulator's) and how far the open hand reaches sideways from its
TCP. The parallel-jaw and the multi-finger grasps share it, so both keep their moves inside
a box and both tell its floor from an object the same way."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from atd.model.controllers import ARM_CONTROLLERS
from primitives.base import Context
from primitives.perception.container import ContainerBelief, clear_of_walls, container_under

# m over the rim above which the hand's lowest point moves at FREE_SPEED, a contact unlikely there: the
# library's objects lying in the box reached at most 9.3 cm up, under the 10 cm rim (docs/empty-the-box.md)
RIM_CLEARANCE = 0.01
FREE_SPEED = float(ARM_CONTROLLERS["cartesian_move"].params["max_speed"].default)  # m/s, a free move's (its spec)


@dataclass(frozen=True)
class KnownWalls:
    """The known containers and the open hand's reach (along its x, along its y; m) either way
    from the middle of its footprint, `offset` from the TCP (m; a multi-finger hand's thumb
    reaches further one way than its fingers the other)."""

    containers: tuple[ContainerBelief, ...]
    extent: tuple[float, float]
    offset: tuple[float, float] = (0.0, 0.0)

    @classmethod
    def of(cls, ctx: Context) -> KnownWalls:
        """From the task's environment and the controller's `hand_extent` and (where it has one)
        `hand_offset` parameters."""
        known = ctx.environment.containers if ctx.environment is not None else ()
        extent, offset = ctx.params["hand_extent"], ctx.params.get("hand_offset", (0.0, 0.0))
        return cls(tuple(ContainerBelief.known(c) for c in known), (float(extent[0]), float(extent[1])),
                   (float(offset[0]), float(offset[1])))

    def inside(self, rotation: np.ndarray, position: np.ndarray, start: np.ndarray | None = None) -> np.ndarray:
        """`position` (world) moved sideways, as little as it takes, for the hand turned by
        `rotation` (world) to stay inside the walls of the container it is over, or that a
        move to it starts over (`start`, world); the same array over none (a grasp on the
        table)."""
        if not self.containers:
            return position
        pose = np.eye(4)
        pose[:3, :3], pose[:3, 3] = rotation, position
        moved = clear_of_walls(list(self.containers), pose, self.extent, start, self.offset)
        return position if moved is pose else moved[:3, 3]

    def rim(self, position: np.ndarray) -> float | None:
        """World z of the rim of the known container `position` (world) is over; None over none."""
        container = container_under(list(self.containers), position)
        return None if container is None else container.rim

    def support(self, position: np.ndarray) -> float:
        """Height of the support under `position` (world): the floor of a known container it
        is over (a box's floor stands its wall's thickness over the table), else the table's
        z = 0."""
        container = container_under(list(self.containers), position)
        return 0.0 if container is None else container.floor
