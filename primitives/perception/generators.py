"""Two of thesis 3.4.3's approach-vector generators as pure functions of what the robot
knows (the container it believes in) and what it sensed: random blind and vision. The third,
blind exploration, has to move the hand to sense, so it is a controller
(`primitives.perception.blind`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from primitives.perception.clusters import euclidean_clusters
from primitives.perception.container import ContainerBelief, approach_pose
from primitives.robot import DepthImage, point_cloud
from primitives.values import Approach

# m below a cluster's highest point whose points give its centre: the top a hand comes down
# on. A camera looking down at a slant also sees the sides facing it: the mean of all its
# points lay 0.4-0.7 cm from a lone 5 cm cube's centre (0.1-0.6 cm from the top's alone), and
# 2.8 cm from a cube's with a 2 cm slab touching it (0.5 cm from the top's; MuJoCo, the
# scripted worlds of tests/primitives/test_perception.py).
TOP_BAND = 0.02


@dataclass(frozen=True)
class Approaching:
    """How high over what it found a generator puts the TCP (see `approach_pose`)."""

    reach: float  # m the hand reaches below its TCP, pointing down
    height: float  # m of clearance between the hand's lowest point and the object's top (or the rim)


def random_blind(container: ContainerBelief, rng: np.random.Generator, margin: float,
                 approaching: Approaching) -> Approach:
    """A top approach at a point drawn uniformly over the container's floor, `margin` in from
    its walls (thesis 3.4.3 random blind). It never says "nothing found": it cannot know."""
    low, high = container.footprint(margin)
    local = np.array([*rng.uniform(low, high), 0.0])
    point = container.to_world(local[None])[0]
    return Approach(approach_pose(container, point, approaching.reach, approaching.height), point, "random_blind")


@dataclass(frozen=True)
class VisionSettings:
    """The vision generator's filter and clustering parameters."""

    floor_margin: float  # m above the floor below which a point is the floor
    wall_margin: float  # m in from the walls outside which a point is a wall
    above_rim: float  # m over the rim up to which objects may pile and still be looked for
    voxel: float  # m, the clustering grid
    min_points: int  # a cluster of fewer is noise


def inside(points: np.ndarray, container: ContainerBelief, settings: VisionSettings) -> np.ndarray:
    """The pass-through filter: the world points within the container's inside, less the floor
    and the walls by their margins, up to `above_rim` over the rim."""
    local = container.to_local(points)
    half = container.inner[:2] / 2 - settings.wall_margin
    keep = (np.abs(local[:, 0]) <= half[0]) & (np.abs(local[:, 1]) <= half[1])
    keep &= (local[:, 2] >= settings.floor_margin) & (local[:, 2] <= container.inner[2] + settings.above_rim)
    return points[keep]


def objects_seen(image: DepthImage, container: ContainerBelief, settings: VisionSettings) -> list[np.ndarray]:
    """The clusters of world points the picture shows inside the container, largest first."""
    points = inside(point_cloud(image), container, settings)
    return [points[members] for members in euclidean_clusters(points, settings.voxel, settings.min_points)]


def top_centre(cluster: np.ndarray) -> np.ndarray:
    """Over the middle of a cluster's top: x y of its points within TOP_BAND of its highest,
    z of its highest."""
    top = float(cluster[:, 2].max())
    near_top = cluster[cluster[:, 2] >= top - TOP_BAND]
    return np.array([*near_top[:, :2].mean(axis=0), top])


def vision(image: DepthImage, container: ContainerBelief, rng: np.random.Generator, settings: VisionSettings,
           approaching: Approaching) -> Approach | None:
    """A top approach over one of the objects the depth image shows in the container, chosen
    at random (thesis 3.4.3 vision); None when it shows none."""
    clusters = objects_seen(image, container, settings)
    if not clusters:
        return None
    point = top_centre(clusters[int(rng.integers(len(clusters)))])
    return Approach(approach_pose(container, point, approaching.reach, approaching.height), point, "vision",
                    len(clusters))
