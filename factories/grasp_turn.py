"""Which way a hand comes down on an object, about the vertical, as a grasp planner turns it:
its pads close across the object's narrowest width as the task believes it stands (a box's
narrow side), and among widths alike (a round object, a square box: the object's symmetry)
the hand turns the least from the yaw it has at home. A gripper closes alike either way
along its line, so no turn need be more than a quarter turn. A hand whose pads open wide
enough to take the object at its home yaw with room to spare keeps it (docs/robust-grasp.md,
"The hand turned to the object")."""

from __future__ import annotations

import math

import numpy as np

from atd.model.task import ObjectInfo
from atd.model.vocabulary import ObjectClass

# m: widths this close are alike (the object's symmetry): a millimetre narrower is no reason to turn the wrist
WIDTH_TIE = 0.001
# m: room the open pads leave around the object along their line at the home yaw that a turn could
# not better: a believed position off by 5 cm either way (the seeds' approach error) still falls
# between them (the Barrett's 25 cm pinch, around any library object; no gripper's 7-8 cm jaws)
ROOM = 0.10


def width_along(obj: ObjectInfo, heading: float) -> float:
    """How wide the object is, as the task believes it stands, along the horizontal line at
    `heading` (rad from the world x): its extent projected on that line."""
    assert obj.pose is not None
    rotation = obj.pose.as_array()[:3, :3]
    u = np.array([math.cos(heading), math.sin(heading), 0.0])
    size = obj.effective_size
    kind = obj.object_class or ObjectClass.BOX
    if kind is ObjectClass.BOX:
        return float(sum(s * abs(float(rotation[:, i] @ u)) for i, s in enumerate(size)))
    if kind is ObjectClass.CYLINDER:
        along = abs(float(rotation[:, 2] @ u))
        return 2.0 * (size[1] / 2 * along + size[0] * math.sqrt(max(0.0, 1.0 - along * along)))
    return 2.0 * size[0]


def grasp_turn(obj: ObjectInfo, closing: float, opening: float) -> float:
    """The turn (rad about the world vertical, within a quarter turn either way) that brings
    a hand whose pads close along world heading `closing` across the object's narrowest
    width; of widths alike, the least turn. The lines tried: the hand's own and, for each of
    the object's axes that is not upright, that axis and the line across it. No turn where the
    pads, `opening` apart, take the object along their home line with ROOM to spare: a turn
    would change where the rest of the hand comes down for nothing the grasp needs."""
    if width_along(obj, closing) + ROOM <= opening:
        return 0.0
    rotation = obj.pose.as_array()[:3, :3] if obj.pose is not None else np.eye(3)
    lines = [closing]
    for axis in rotation.T:
        if math.hypot(axis[0], axis[1]) > 1e-6:
            heading = math.atan2(axis[1], axis[0])
            lines += [heading, heading + math.pi / 2]
    turns = [(line - closing + math.pi / 2) % math.pi - math.pi / 2 for line in lines]
    widths = [width_along(obj, closing + turn) for turn in turns]
    narrowest = min(widths)
    return min((t for t, w in zip(turns, widths) if w <= narrowest + WIDTH_TIE), key=abs)
