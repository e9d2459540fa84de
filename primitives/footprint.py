"""Where the task believes its object stands on the support: which points lie over its
footprint. A slide tells the fingers on the object from those hanging behind it by that
footprint; the robust grasp tells a pad on the object's foot from one on the table."""

from __future__ import annotations

import numpy as np

from atd.model.task import ObjectInfo
from atd.model.vocabulary import ObjectClass


def over_footprint(obj: ObjectInfo | None, points: np.ndarray, margin: float = 0.0) -> np.ndarray:
    """Which of `points` (world, n x 3) lie over the object's footprint where the task
    believes it stands, widened by `margin`: a box's resting face, turned as its pose turns
    it; a round object's disc. All of them where the task believes no pose."""
    if obj is None or obj.pose is None:
        return np.ones(len(points), bool)
    pose = obj.pose.as_array()
    local = (points - pose[:3, 3]) @ pose[:3, :3]
    size = obj.effective_size
    if (obj.object_class or ObjectClass.BOX) is ObjectClass.BOX:
        return np.all(np.abs(local[:, :2]) <= np.array(size[:2]) / 2 + margin, axis=1)
    return np.hypot(local[:, 0], local[:, 1]) <= size[0] + margin
