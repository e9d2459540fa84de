"""A ball under the descent of parallel jaws whose pads feel no tactile image (the Baxter's
paddles): the jaw grasp's arm knows it only through the wrist (docs/robust-grasp.md, "The
ball kicked by the paddles' descent").

A finger's lower edge that comes down on a ball's upper flank presses it into the table and
squeezes it out sideways: at the descent's 4 cm/s PyBullet's ball left at 6.5-8.5 cm/s and
rolled 5-14 cm, out of any search's reach. Through the ball's upper half the descent goes
slower. And where the wrist then feels the contact says which finger met the ball, not
where the ball is: a ball's centre lies a flank's width `d` from that edge, inside it (between
the fingers) or beyond it, and the contact's push across the jaws says which: the ball pushes
the finger away from its centre.
"""

from __future__ import annotations

import numpy as np

from atd.model.vocabulary import ObjectClass
from primitives.base import Context

# of `descent_velocity`, while the open fingertips pass a ball's upper half: a kick leaves at
# about the descent's speed, and a ball rolls v^2 / 2a, 3 cm from 4 cm/s but 2 mm from 1 cm/s
# (the library's rolling friction, a = 0.028 m/s^2)
ROLLING_DESCENT = 0.25
ROLLING_MARGIN = 0.01  # m over the ball's top where that begins: a tilted hand's fingertip reads a few mm off


class BallUnderJaws:
    """The ball the task believes in, as jaws from above without tactile images meet it."""

    def __init__(self, centre_z: float, radius: float, reach_across: float) -> None:
        self.centre_z = centre_z  # m, world
        self.radius = radius  # m
        self.reach_across = reach_across  # m the open fingertips reach from the TCP's axis across the jaws

    @classmethod
    def of(cls, ctx: Context, reach_across: float, vertical: bool) -> BallUnderJaws | None:
        """The task's ball, for a hand from above whose pads give no tactile image; None otherwise."""
        obj = ctx.object
        if not vertical or obj is None or obj.pose is None or obj.object_class is not ObjectClass.SPHERE \
                or any(pad.taxels is not None for pad in ctx.info.hand.pads):
            return None
        return cls(float(obj.pose.position[2]), obj.half_height, reach_across)

    def passing(self, tips_z: float) -> bool:
        """The open fingertips' lowest point (world z) is within the ball's upper half, or just over it."""
        return self.centre_z <= tips_z <= self.centre_z + self.radius + ROLLING_MARGIN

    def centre_across(self, lever: float, push: float, tips_z: float) -> float:
        """Where across the jaws (hand y) the ball's centre lies, for a descent's contact the
        wrist's lever places at `lever` (the finger that met it: its side) pushed across by
        `push` (N, hand y) with the fingertips at `tips_z`: a flank's width `d` from the
        finger's reach, inside it where the push is outwards, else beyond it. The reach is
        the finger's outer extent: the wrist reads the contact a few mm down the flank, by
        then `d` is that much wider (docs/robust-grasp.md has the traced contacts)."""
        side = 1.0 if lever >= 0.0 else -1.0
        height = float(np.clip(tips_z - self.centre_z, 0.0, self.radius))
        flank = float(np.sqrt(self.radius**2 - height**2))
        inside = push * side > 0.0
        return side * (self.reach_across - flank if inside else self.reach_across + flank)
