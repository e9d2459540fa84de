"""Two of thesis 3.4.3's approach-vector generators as pure functions of what the robot
knows (the container it believes in) and what it sensed: random blind and vision. The third,
blind exploration, has to move the hand to sense, so it is a controller
(`primitives.perception.blind`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from atd.model.frames import axis_rotation
from primitives.perception.clusters import euclidean_clusters
from primitives.perception.container import ContainerBelief, approach_pose, clear_of_walls
from primitives.robot import DepthImage, point_cloud
from primitives.values import Approach

# m below a cluster's highest point whose points give its centre: the top a hand comes down
# on. A camera looking down at a slant also sees the sides facing it: the mean of all its
# points lay 0.4-0.7 cm from a lone 5 cm cube's centre (0.1-0.6 cm from the top's alone), and
# 2.8 cm from a cube's with a 2 cm slab touching it (0.5 cm from the top's; MuJoCo, the
# scripted worlds of tests/primitives/test_perception.py).
TOP_BAND = 0.02
# An object's top this much longer one way than the other has a long side for the jaws to
# close across; a rounder one (a ball, a roll of tape seen on end) is taken along the
# container's own axes.
ELONGATED = 1.3
# m a wall may push the jaws off an object's centre along their closing axis before the other
# way round is the better grasp: the WRT-102's jaws open 68 mm, a 5 cm object leaves 9 mm a side.
WALL_PUSH = 0.01
# m (x y) from a cluster's nearest point within which an earlier round's approach was aimed at
# it: a grasp that misses nudges what it came down on by a centimetre or two, and the library's
# objects lie 3.8 cm or more apart at their middles.
AIMED_NEAR = 0.02
# The turns (rad from the container's x) and the slides along the jaws' closing axis (m) off the
# middle aimed at that vision weighs where the jaws' first choice would come down on something:
# every 15 degrees, and up to 1.5 cm either way (the library's objects are 3.8 cm or more across,
# the WRT-102's jaws open 6.8 cm: a slide further leaves no object between them).
CLEARING_TURNS = np.radians(np.arange(-90.0, 90.0, 15.0))
CLEARING_SLIDES = (0.0, -0.005, 0.005, -0.01, 0.01, -0.015, 0.015)
# m the jaws' fingertips are taken to reach further, outwards and along the hand's x, than the
# hand's geometry says: the arm reaches an approach to within 3 mm, and the picture's points stop a
# few mm short of an object's edge
JAW_MARGIN = 0.005


@dataclass(frozen=True)
class Approaching:
    """How high over what it found a generator puts the TCP (see `approach_pose`)."""

    reach: float  # m the hand reaches below its TCP, pointing down, as it perceives (a sweep's hand)
    height: float  # m of clearance between the hand's lowest point and the object's top (or the rim)
    # m the hand reaches below its TCP in the posture that reaches furthest: the grasp after
    # the approach opens it (an SDH2 perceives closed, 9.3 cm short of its TCP, and opens to
    # 2.1 cm past it), so the approach keeps that much clear of the rim
    grasp_reach: float


def random_blind(container: ContainerBelief, rng: np.random.Generator, extent: tuple[float, float],
                 approaching: Approaching) -> Approach:
    """A top approach at a point drawn uniformly over the container's whole floor (thesis 3.4.3
    random blind: anywhere inside the known box). Where the walls leave the open hand (reaching
    `extent` along its x and its y) no room over that point, the hand is moved in as little as
    it takes (`clear_of_walls`), turned so that its jaws close along the wall it is moved off
    where that pushes them less off the point: an object lying against a wall is then between
    the jaws, not under one. It never says "nothing found": it cannot know."""
    low, high = container.footprint(0.0)
    point = container.to_world(np.array([[*rng.uniform(low, high), 0.0]]))[0]
    pushes = [walls_push(container, approach_pose(container, point, approaching.grasp_reach, approaching.height, yaw),
                         extent) for yaw in (0.0, np.pi / 2)]
    moved = min(pushes, key=lambda push: push[0])[1]  # jaws along the box's y on a tie
    return Approach(moved, np.array([*moved[:2, 3], point[2]]), "random_blind")


def walls_push(container: ContainerBelief, pose: np.ndarray, extent: tuple[float, float],
               offset: tuple[float, float] = (0.0, 0.0)) -> tuple[float, np.ndarray]:
    """How far (m) the container's walls push a top-down hand at `pose` (reaching `extent`
    either way from the middle of its footprint, `offset` from the pose; `clear_of_walls`) along
    its jaws' closing axis (its y) to keep it inside them, and the pose they leave it at."""
    moved = clear_of_walls([container], pose, extent, offset=offset)
    return abs(float((moved[:3, 3] - pose[:3, 3]) @ pose[:3, 1])), moved


@dataclass(frozen=True)
class VisionSettings:
    """The vision generator's filter and clustering parameters."""

    floor_margin: float  # m above the floor below which a point is the floor
    wall_margin: float  # m in from the walls outside which a point is a wall
    above_rim: float  # m over the rim up to which objects may pile and still be looked for
    voxel: float  # m, the clustering grid
    min_points: int  # a cluster of fewer is noise
    grasp_extent: tuple[float, float]  # m the open hand reaches sideways along its x and its y (the jaws' closing)
    # m, the open jaws' fingertips: from how far along the hand's y their inner faces stand to how far
    # they reach, and how far along its x; zeros: not known, the jaws' turn is chosen by the top alone
    jaw_band: tuple[float, float, float] = (0.0, 0.0, 0.0)
    # m, the rectangle a hand reaching further one way than the other (the SDH2's thumb) covers as it
    # comes down to grasp: how far either way from its middle along the hand's x and y, and where that
    # middle lies from the point it grasps at; zeros: a hand alike either way round (`grasp_extent`)
    footprint: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0)
    # rad the hand turns about its approach axis from the axes `footprint` is given along, whose y
    # is the line its grasp closes along: the Barrett's pinch closes along its x, a quarter turn
    turn: float = 0.0
    # m, the hand's other lowest links about where its fingers close (the SDH2's thumb): from and to
    # along the hand's x, and either way along its y; zeros: none
    other_tips: tuple[float, float, float] = (0.0, 0.0, 0.0)

    @property
    def walls(self) -> tuple[tuple[float, float], tuple[float, float]]:
        """How far the hand reaches either way from its footprint's middle, and that middle's offset."""
        if not any(self.footprint):
            return self.grasp_extent, (0.0, 0.0)
        return self.footprint[:2], self.footprint[2:]


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


def top_centre(top: np.ndarray) -> np.ndarray:
    """Over the middle of a top (a cluster's points within TOP_BAND of its highest, or a part
    of them): x y of their mean, z of their highest."""
    return np.array([*top[:, :2].mean(axis=0), float(top[:, 2].max())])


def near_top(cluster: np.ndarray) -> np.ndarray:
    """A cluster's points within TOP_BAND of its highest: the top a hand comes down on."""
    return cluster[cluster[:, 2] >= float(cluster[:, 2].max()) - TOP_BAND]


def principal_axis(top: np.ndarray, container: ContainerBelief) -> tuple[np.ndarray, bool]:
    """The long axis of a top (its points, world) as a unit x y vector of the container's
    frame, and whether it is a clear one (ELONGATED); the container's x for under 3 points."""
    local = container.to_local(top)[:, :2]
    if len(local) < 3:
        return np.array([1.0, 0.0]), False
    spread, axes = np.linalg.eigh(np.cov(local.T))
    return axes[:, 1], bool(spread[1] >= ELONGATED**2 * max(spread[0], 1e-12))


def long_side(top: np.ndarray, container: ContainerBelief, halved: bool = False) -> float:
    """The yaw (rad, from the container's x, within a quarter turn of it) of the long axis of
    an object's top (its points, world), so that jaws closing along the hand's y close across
    its narrow side; 0 for a top with no clear long axis, unless it is `halved` (split across
    that axis by `part_to_aim_at`, clear or not)."""
    (x, y), clear = principal_axis(top, container)
    if not clear and not halved:
        return 0.0
    yaw = float(np.arctan2(y, x))
    return float((yaw + np.pi / 2) % np.pi - np.pi / 2)


def jaw_yaw(top: np.ndarray, container: ContainerBelief, extent: tuple[float, float],
            half: np.ndarray | None = None, offset: tuple[float, float] = (0.0, 0.0)) -> float:
    """The yaw (see `approach_pose`) for jaws closing along the hand's y over an object's top
    (its points, world), or over the `half` of it aimed at: of the two ways along and across its
    long side, one whose jaws the walls leave room to open over the middle aimed at (pushed less
    than WALL_PUSH off it along the closing axis), then the one that closes across the narrower
    width; over a half, across the axis it was split along: along that axis lies the other half,
    the rest of one object or a neighbour touching it, and a jaw closing that way lands on it.
    A hand whose footprint's middle lies `offset` off its grasp point (`clear_of_walls`) is
    taken each way round at the half turn that leaves it room (`roomier_half`)."""
    long = long_side(top, container, half is not None)
    centre = np.array([*(top if half is None else half)[:, :2].mean(axis=0), container.rim])

    turned = {yaw: roomier_half(container, centre, yaw, extent, offset)
              for yaw in (long, (long + np.pi) % np.pi - np.pi / 2)}

    def cost(yaw: float) -> tuple[bool, float]:
        pose = approach_pose(container, centre, 0.0, 0.0, turned[yaw])
        pushed = walls_push(container, pose, extent, offset)[0]
        width = float(np.ptp(top[:, :2] @ pose[:2, 1]))
        return pushed > WALL_PUSH, 0.0 if half is not None and yaw == long else width

    return turned[min(turned, key=cost)]


def roomier_half(container: ContainerBelief, point: np.ndarray, yaw: float, extent: tuple[float, float],
                 offset: tuple[float, float]) -> float:
    """Of `yaw` and half a turn further (the same closing line), the one whose hand, its
    footprint's middle `offset` off its grasp point, the walls push less off `point` (along the
    closing axis, then at all): the SDH2's thumb, reaching 8.9 cm to its fingers' 5.0, towards
    the middle of the box. `yaw` itself for a hand alike either way round (`offset` zero)."""
    if not any(offset):
        return yaw

    def pushed(turn: float) -> tuple[float, float]:
        pose = approach_pose(container, point, 0.0, 0.0, turn)
        along, moved = walls_push(container, pose, extent, offset)
        return round(along, 6), float(np.linalg.norm(moved[:2, 3] - pose[:2, 3]))

    return min((yaw, yaw + np.pi), key=pushed)


def under_jaws(points: np.ndarray, pose: np.ndarray, band: tuple[float, float, float],
               others: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> int:
    """How many of `points` (world) lie under the open jaws' fingertips of a top-down hand at
    `pose` (reaching `band`, see VisionSettings, and JAW_MARGIN further out), or under its other
    lowest links (`others`, VisionSettings.other_tips): what a jaw, or a thumb, coming down
    there lands on."""
    flat = points[:, :2] - pose[:2, 3]
    x, y = flat @ pose[:2, 0], flat @ pose[:2, 1]
    along, across = np.abs(y), np.abs(x)
    under = (along >= band[0]) & (along <= band[1] + JAW_MARGIN) & (across <= band[2] + JAW_MARGIN)
    if any(others):
        under |= (x >= others[0] - JAW_MARGIN) & (x <= others[1] + JAW_MARGIN) & (along <= others[2] + JAW_MARGIN)
    return int(np.count_nonzero(under))


def clear_jaws(pose: np.ndarray, point: np.ndarray, seen: np.ndarray, container: ContainerBelief,
               settings: VisionSettings) -> np.ndarray:
    """The approach `pose` over `point`, or, where its open jaws (`jaw_band`), kept inside the
    walls as the grasp keeps them, would come down on something the picture shows (`seen`: a
    neighbour, the object itself where it is wider that way than the jaws open, or pushed under
    a jaw by a wall), the turn (CLEARING_TURNS) and slide along the closing axis
    (CLEARING_SLIDES) that leave the fewest points under them, then the least slide, then the
    least turn from `pose`'s: a jaw on something as high as the top stops the grasp's descent
    there (docs/empty-the-box.md, "Jaws kept off what the picture shows"). A hand whose
    footprint lies off its grasp point (`VisionSettings.walls`) is kept inside the walls by
    that footprint and takes each turn at its roomier half (`roomier_half`), as `jaw_yaw` does."""
    band, (extent, offset) = settings.jaw_band, settings.walls
    if band[1] <= 0.0:
        return pose

    def landed(candidate: np.ndarray) -> int:
        return under_jaws(seen, clear_of_walls([container], candidate, extent, offset=offset), band,
                          settings.other_tips)

    if landed(pose) == 0:
        return pose
    first = float(np.arctan2(pose[1, 1], pose[0, 1]))  # the hand's y, the closing axis, in the world

    def turned(turn: float, slide: float) -> np.ndarray:
        candidate = approach_pose(container, point, 0.0, 0.0, roomier_half(container, point, turn, extent, offset))
        candidate[:3, 3] = pose[:3, 3] + slide * candidate[:3, 1]
        return candidate

    def cost(candidate: np.ndarray, slide: float) -> tuple[int, float, float]:
        off = float(np.arctan2(candidate[1, 1], candidate[0, 1])) - first
        return landed(candidate), abs(slide), abs((off + np.pi / 2) % np.pi - np.pi / 2)

    return min(((turned(turn, slide), slide) for turn in CLEARING_TURNS for slide in CLEARING_SLIDES),
               key=lambda pair: cost(*pair))[0]


def aimed_at(cluster: np.ndarray, aimed: Sequence[np.ndarray]) -> list[np.ndarray]:
    """The earlier approaches' points (`aimed`, world) aimed at this cluster: within
    AIMED_NEAR of one of its points, across."""
    flat = cluster[:, :2]
    return [point for point in aimed if float(np.min(np.hypot(*(flat - point[:2]).T))) <= AIMED_NEAR]


def part_to_aim_at(top: np.ndarray, container: ContainerBelief, earlier: Sequence[np.ndarray]) -> np.ndarray:
    """The points of a cluster's top (world) to aim at: all of it, or, after earlier rounds
    aimed at it (`earlier`, their points) and missed, of it and its two halves (split across
    its long axis at its middle) the one aimed at least near its middle, then furthest from
    where they aimed. Two objects touching, their tops alike, are one cluster whose middle is
    the seam between them, and every round aimed there closed on nothing; its halves are the
    objects (or, for one long object, grips off its middle)."""
    if not earlier:
        return top
    axis, _ = principal_axis(top, container)
    along = container.to_local(top)[:, :2] @ axis
    middle = float(np.median(along))
    parts = [part for part in (top, top[along < middle], top[along >= middle]) if len(part) >= 3]

    def unaimed(part: np.ndarray) -> tuple[int, float]:
        """Fewer aims within AIMED_NEAR of its middle, then the nearest aim further off."""
        off = [float(np.hypot(*(top_centre(part)[:2] - point[:2]))) for point in earlier]
        return -sum(d <= AIMED_NEAR for d in off), min(off)

    return max(parts, key=unaimed)  # the whole top first, on a tie


def vision(image: DepthImage, container: ContainerBelief, rng: np.random.Generator, settings: VisionSettings,
           approaching: Approaching, aimed: Sequence[np.ndarray] = ()) -> Approach | None:
    """A top approach over one of the objects the depth image shows in the container, chosen
    at random (thesis 3.4.3 vision) among those the earlier approaches (`aimed`, their points)
    were aimed at least often: an object still there after a round aimed at it was missed, and
    the next round tries another first; over the middle of its top, or of the part of it that
    the earlier rounds' misses leave (`part_to_aim_at`). Turned for the jaws to close across
    its narrow side (across the split, over a part) where the walls leave them room
    (`jaw_yaw`), turned or slid further where the open jaws would come down on something the
    picture shows (`clear_jaws`), and for a hand whose grasp closes along another line than
    its y, turned to close along that one (`closing_turned`); None when it shows none."""
    clusters = objects_seen(image, container, settings)
    if not clusters:
        return None
    counts = [len(aimed_at(cluster, aimed)) for cluster in clusters]
    least = [cluster for cluster, count in zip(clusters, counts) if count == min(counts)]
    chosen = least[int(rng.integers(len(least)))]
    top = near_top(chosen)
    part = part_to_aim_at(top, container, aimed_at(chosen, aimed))
    point = top_centre(part)
    extent, offset = settings.walls
    pose = approach_pose(container, point, approaching.grasp_reach, approaching.height,
                         jaw_yaw(top, container, extent, part if len(part) < len(top) else None, offset))
    pose = closing_turned(clear_jaws(pose, point, np.concatenate(clusters), container, settings), settings.turn)
    return Approach(pose, point, "vision", len(clusters), float(point[2]), either_way=not any(offset))


def closing_turned(pose: np.ndarray, turn: float) -> np.ndarray:
    """The hand's pose for an approach `pose` turned for a grasp closing along its y: turned
    `turn` (rad) about its own approach axis, so that a hand closing along another line
    (the Barrett's pinch, along its x) closes along that y."""
    if turn == 0.0:
        return pose
    turned = pose.copy()
    turned[:3, :3] = pose[:3, :3] @ axis_rotation(np.array([0.0, 0.0, 1.0]), turn)
    return turned
