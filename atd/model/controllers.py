"""The ESTD vocabulary: every concrete controller and condition an ESTD may name.

This module is the one contract between the two sides of an ESTD. Factories choose
names from it and fill in parameters; the runtime implements exactly these names and
reads the parameters by the names given here. Defaults are the thesis values of
chapter 3.3 where the thesis gives one (cited per parameter), otherwise ours (marked).

Per D5 2.2.4 every ESTD state runs one arm controller and one hand controller at the
same time; the runtime's arbitrator merges their outputs per degree of freedom. A leaf
condition reads sensors of one kind (wrist force-torque, tactile pads, gripper, range)
and holds or not at each control step.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import StrEnum
from types import MappingProxyType
from typing import Mapping, Union

import atd.model.ranges as ranges
from atd.model.ranges import Range

ParamValue = Union[bool, int, float, str, tuple[float, ...], tuple[tuple[float, ...], ...]]


class Role(StrEnum):
    ARM = "arm"
    HAND = "hand"


class SensorKind(StrEnum):
    """What a sensor measures, so a condition can check it names sensors it can read."""

    FORCE_TORQUE = "force_torque"  # 6-axis wrist wrench, hand frame (see docs/estd.md)
    TACTILE = "tactile"  # one pad: total normal force in N
    GRIPPER = "gripper"  # parallel gripper: jaw opening in m and motor force in N
    RANGE = "range"  # distance in m along the hand's approach axis


class ParamType(StrEnum):
    NUMBER = "number"  # float
    INTEGER = "integer"
    FLAG = "flag"  # bool, written true/false
    WORD = "word"  # str
    VECTOR = "vector"  # fixed-length tuple of floats, written space-separated
    POINTS = "points"  # tuple of 3-vectors, written "x y z; x y z"

    @property
    def with_article(self) -> str:
        return f"{'an' if self.value[0] in 'aeiou' else 'a'} {self.value}"


@dataclass(frozen=True)
class ParamSpec:
    """One parameter: its type, meaning, unit and default.

    A parameter with no default is either required (a factory must set it, e.g. a
    target) or optional (omitted when unset, e.g. PREGRASP_SIZE "default: none").
    Only parameters with a default are tunable in a robot config file: the others,
    and point lists (waypoints, obstacles), come from the task.
    """

    type: ParamType
    doc: str
    default: ParamValue | None = None
    required: bool = False
    unit: str = ""
    length: int | None = None  # VECTOR only
    choices: tuple[str, ...] = ()  # WORD only; empty = free text
    limits: Range | None = None  # when not given: by the unit for numbers, coordinates for vectors

    @property
    def tunable(self) -> bool:
        return self.default is not None and self.type is not ParamType.POINTS

    @property
    def allowed(self) -> Range:
        """The range each number of this parameter must lie in (see atd.model.ranges)."""
        if self.limits is not None:
            return self.limits
        if self.type in (ParamType.VECTOR, ParamType.POINTS):
            return ranges.COORDINATE
        if self.type is ParamType.INTEGER:
            return ranges.COUNT
        return ranges.BY_UNIT[self.unit]


@dataclass(frozen=True)
class ControllerSpec:
    name: str
    role: Role
    doc: str
    source: str  # where the control law comes from
    params: Mapping[str, ParamSpec] = field(default_factory=dict)


@dataclass(frozen=True)
class ConditionSpec:
    kind: str
    doc: str
    reads: SensorKind | None = None  # leaves of this kind name >= 1 sensor of this kind
    params: Mapping[str, ParamSpec] = field(default_factory=dict)


def _p(type_: ParamType, doc: str, default: ParamValue | None = None, *, unit: str = "",
       required: bool = False, length: int | None = None, choices: tuple[str, ...] = (),
       limits: Range | None = None) -> ParamSpec:
    return ParamSpec(type_, doc, default, required, unit, length, choices, limits)


NUM, VEC, FLAG, WORD, PTS, INT = (ParamType.NUMBER, ParamType.VECTOR, ParamType.FLAG, ParamType.WORD,
                                  ParamType.POINTS, ParamType.INTEGER)

# Parameters shared by several controllers, defined once.
_TARGET = _p(VEC, "TCP position to reach, ATD world frame", unit="m", required=True, length=3)
_SURFACE_NORMAL = _p(VEC, "normal of the supporting surface, world frame (thesis 3.3.3-3.3.5)", (0.0, 0.0, 1.0),
                     length=3, limits=ranges.DIRECTION)
_FILTER = _p(NUM, "time constant of the first-order low-pass applied to the wrench before thresholding "
                "(ours; 0 = raw)", 0.0, unit="s")
_WRIST_TO_TCP = _p(NUM, "how far the TCP lies beyond the wrist sensor along the hand's z axis, to place a "
                   "contact from the wrist's torque (the robot's own geometry)", 0.1, unit="m")
_FORCE_SOURCE = _p(WORD, "what measures the grip force: the tactile pads or the gripper motor", "tactile",
                   choices=("tactile", "motor"))
_FOR = _p(NUM, "the condition must hold this long without a break before it fires (ours; 0 = at once)",
          0.0, unit="s")

# How explore moves, and the explore moves a blind exploration makes.
_EXPLORING = {
    "speed": _p(NUM, "speed of an explore move (ours)", 0.04, unit="m/s"),
    "force_threshold": _p(NUM, "force over the start's, on the wrist or a pad, that is a contact (ours, over "
                          "the robust grasp's 2 N)", 3.0, unit="N"),
    "filter_time": _FILTER,
}

# cartesian_move's parameters; push takes them too, with its own defaults where it differs.
_MOVE = {
    "target": _TARGET,
    "waypoints": _p(PTS, "via points before the target (thesis WAYPOINTS)", ()),
    "obstacles": _p(PTS, "centres of boxes to keep clear of (thesis 3.3.2 OBSTACLES)", ()),
    "obstacle_sizes": _p(PTS, "full x y z size of each obstacle box, same order as obstacles", (),
                         limits=ranges.OBSTACLE_EXTENT),
    "straight_line": _p(FLAG, "follow the straight Cartesian line (guarded motion, thesis 7.2)", False),
    "keep_orientation": _p(FLAG, "hold the hand orientation all along (constrained motion, thesis 7.2); "
                          "otherwise only the final orientation is the starting one", False),
    "force_threshold": _p(NUM, "unexpected-contact force (thesis 3.3.2 FORCE_THRESHOLD)", 15.0, unit="N"),
    "max_speed": _p(NUM, "TCP speed limit (ours; the thesis' VELOCITY_LIMITS zeros mean 'none')", 0.15,
                    unit="m/s"),
    "velocity_limits": _p(VEC, "linear and angular velocity limits; zeros = none (thesis 3.3.2)",
                          (0.0,) * 6, length=6, limits=ranges.LIMITS),
    "acceleration_limits": _p(VEC, "linear and angular acceleration limits; zeros = none (thesis 3.3.2)",
                              (0.0,) * 6, length=6, limits=ranges.LIMITS),
    "tolerance": _p(NUM, "distance to the target counted as reached (ours)", 0.003, unit="m"),
    "tilt": _p(VEC, "the hand turned away from top-down at the target: roll, pitch, yaw about the world axes "
                    "(ours: an oriented approach, thesis 3.4.1; zeros: top-down)", (0.0, 0.0, 0.0), unit="deg",
               length=3, limits=ranges.TILT),
    "level": _p(FLAG, "turn the hand top-down (keeping its yaw), then by tilt; off, the hand keeps the orientation "
                      "it starts with, turned by tilt: a transport carries the object as the grasp left it (ours)",
                True),
    "yaw": _p(NUM, "the hand's x at the target, about the world vertical from the world x, or the opposite way "
                   "if that is the smaller turn (parallel jaws grip alike either way) and keeps the hand within 135 "
                   "degrees of where the first such turn started; unset keeps the yaw it starts with. A target from "
                   "an approach sets it to the approach's (ours, thesis 3.4.3)", unit="deg",
              limits=ranges.YAW),
    "either_way": _p(FLAG, "with yaw: the opposite way too where that is the smaller turn; off, that yaw itself, "
                           "the way the factory rehearsed for a wrist kept off its stops (ours, issue 33)", True),
    "wrist_roll": _p(NUM, "with yaw: how the last arm joint turns per turn of the hand about the vertical, +1 or -1 "
                          "(0: none rolls it); the opposite way is taken where the nearer would leave that joint "
                          "less than 15 degrees from a limit and the other leaves it more (the robot's own geometry)",
                     0.0, limits=ranges.DIRECTION),
    "hand_point": _p(VEC, "the point of the hand the target is for, from the TCP in the hand frame at the target: "
                     "a target read from a named value is for where the state's hand shape acts (the SDH2's "
                     "pinch, 19 mm off its TCP; at a point an explore touched, the hand's lowest point under it), "
                     "so the TCP stops that far from it (ours); zeros: the TCP",
                     (0.0, 0.0, 0.0), unit="m", length=3),
    "contact_margin": _p(NUM, "how near the target a contact must come to end a guarded move as arrived (a place "
                         "meeting its surface); one further away stops it short, an error (a transport meeting "
                         "resistance); negative = any contact, for a move that looks for one (ours)", -1.0, unit="m",
                         limits=ranges.CONTACT_MARGIN),
    "filter_time": _FILTER,
}

_ARM_CONTROLLERS = (
    ControllerSpec("hold", Role.ARM, "Keep the TCP where it was when the state began.", "D5 2.2.4 (arm idle)"),
    ControllerSpec(
        "cartesian_move", Role.ARM,
        "Move the TCP to the target through the waypoints with a Cartesian velocity law; stop on an "
        "unexpected contact (||F|| >= force_threshold).",
        "thesis 3.3.2, Eq. 3.3 (transport)",
        _MOVE,
    ),
    ControllerSpec(
        "push", Role.ARM,
        "Push the object along the path: a guarded move that must feel the object, so reaching the target "
        "without a force against the motion (push_force over its free-motion level) is an error, and so "
        "is an object that does not give way (||F|| >= force_threshold).",
        "thesis 3.3.2, Eq. 3.3 (guarded transport); Table 7.1 push",
        {
            **_MOVE,
            "straight_line": _p(FLAG, "follow the straight Cartesian line (a push is a guarded motion)", True),
            "force_threshold": _p(NUM, "the object does not give way: the push fails (thesis 3.3.2 "
                                  "FORCE_THRESHOLD)", 15.0, unit="N"),
            "max_speed": _p(NUM, "TCP speed limit: slow, so the object slides instead of being struck (ours)",
                            0.05, unit="m/s"),
            "push_force": _p(NUM, "force against the motion, over the level measured in free motion, that says "
                             "the hand is pushing something (ours: a 0.1 kg box on the table resists with "
                             "about 0.5 N)", 0.25, unit="N"),
            "push_time": _p(NUM, "time constant of the low-pass on that force (ours)", 0.2, unit="s"),
            "baseline_time": _p(NUM, "how long the free-motion level is measured once the TCP cruises, before "
                                "the hand meets the object (ours)", 0.3, unit="s"),
        },
    ),
    ControllerSpec(
        "robust_grasp_approach", Role.ARM,
        "Arm side of the robust grasp: move along the grasp direction until contact, align on the "
        "wrist torque, then slide on the supporting surface while the fingers close.",
        "thesis 3.3.1, Eq. 3.1 (alignment) and 3.2 (sliding grasp)",
        {
            "grasp_direction": _p(VEC, "approach direction in the hand frame (thesis GRASP_DIRECTION)",
                                  (0.0, 0.0, 1.0), length=3, limits=ranges.DIRECTION),
            "max_distance": _p(NUM, "how far to look for a contact (thesis MAX_DISTANCE)", 0.2, unit="m"),
            "force_threshold": _p(NUM, "contact force on the wrist (thesis FORCE_THRESHOLD)", 2.0, unit="N"),
            "torque_threshold": _p(NUM, "alignment torque (thesis TORQUE_THRESHOLD)", 5.0, unit="N m"),
            "correction_velocity": _p(NUM, "speed of corrective motions (thesis CORRECTION_VELOCITY)", 0.005,
                                      unit="m/s"),
            "level_within": _p(NUM, "a grasp direction this close to the vertical is a grasp from above: the hand "
                               "turns level first (ours; 0 keeps the tilt the approach left)", 30.0, unit="deg",
                               limits=ranges.ANGLE),
            "approach_velocity": _p(NUM, "speed along the grasp direction before the first contact (ours: at the "
                                    "correction velocity a 4 cm descent took 8 of the grasp's 20 s)", 0.03,
                                    unit="m/s"),
            "backoff_velocity": _p(NUM, "speed of the sliding grasp's back-off from a surface the fingertips press "
                                   "on (ours: at the correction velocity, closing fingers waited 4-5 s per close "
                                   "for the hand to rise)", 0.02, unit="m/s"),
            "follow_surface": _p(FLAG, "the sliding grasp moves the hand on along the grasp direction once the "
                                 "surface's push is gone (Eq. 3.2); off, it only backs off the surface (ours: the "
                                 "robot's hand description says which grasps lift their fingertips as they close)",
                                 True),
            "centre_band": _p(NUM, "an approach's first contact above the support and more than this far off the "
                              "grasp centre, across the hand, is a finger on the object's top: the hand moves "
                              "over it (ours)", 0.02, unit="m"),
            "max_shift": _p(NUM, "largest such move across (ours: the seeds' error is up to 5 cm per axis)",
                            0.05, unit="m"),
            "max_shifts": _p(INT, "how many times to move across (ours)", 2),
            "clearance": _p(NUM, "how far to rise off the contact before moving across (ours)", 0.02, unit="m"),
            "wrist_to_tcp": _WRIST_TO_TCP,
            "fingertip_reach": _p(NUM, "how far the preshaped fingertips reach beyond the TCP along the hand's z "
                                  "axis: a contact is placed at their depth (the robot's own geometry)", 0.02,
                                  unit="m"),
            "grasp_centre": _p(VEC, "where the grasp closes, from the TCP in the hand frame (the robot's own "
                               "geometry: the SDH2 pinches 19 mm off its TCP)", (0.0, 0.0, 0.0), length=3,
                               limits=ranges.COORDINATE),
            "max_back_off": _p(NUM, "how far the sliding grasp may back off above where it began (the robot's "
                               "own geometry: how far its fingertips swing down as they close, and 5 mm; the "
                               "default covers the Barrett pinch's 18 mm)", 0.025, unit="m"),
            "hand_extent": _p(VEC, "how far the preshaped hand reaches sideways either way from the middle of its "
                              "footprint (`hand_offset`), along the hand's x and along its y: its moves stay this far "
                              "inside the walls of a container the task knows (the robot's own geometry: "
                              "`RobotDescription.hand_sides`)", (0.1, 0.1), unit="m", length=2),
            "hand_offset": _p(VEC, "where the middle of the preshaped hand's footprint lies from the TCP, along the "
                              "hand's x and along its y: a hand reaching further one way than the other (the SDH2's "
                              "thumb) comes nearer a wall with its shorter side towards it (the robot's own geometry: "
                              "`RobotDescription.hand_sides`)", (0.0, 0.0), unit="m", length=2,
                              limits=ranges.COORDINATE),
            "filter_time": _FILTER,
        },
    ),
    ControllerSpec(
        "jaw_grasp_correction", Role.ARM,
        "Arm side of the robust parallel-jaw grasp: rise above the object's top, descend on the wrist "
        "sensor; a contact under one jaw moves the hand across by where it sits, jaws closing on "
        "nothing send the hand to the next point of a search along the jaws' width; then follow the "
        "gripper's re-centring while it closes.",
        "thesis 3.3.1 (contact-driven corrections); D5 chapter 3 (parallel jaws)",
        {
            "force_threshold": _p(NUM, "contact force on the wrist (thesis FORCE_THRESHOLD)", 2.0, unit="N"),
            "correction_velocity": _p(NUM, "speed of the corrective moves across and up (ours; the thesis' "
                                      "5 mm/s would spend the grasp's timeout on one correction)", 0.05,
                                      unit="m/s"),
            "descent_velocity": _p(NUM, "speed of the descent onto the object (ours)", 0.04, unit="m/s"),
            "clearance": _p(NUM, "how far to rise before a correction (ours)", 0.02, unit="m"),
            "above_object": _p(NUM, "the first descent starts with the TCP this far above the object's top, "
                               "so the fingertips clear it (ours: more than a fingertip's reach below the "
                               "TCP)", 0.04, unit="m"),
            "back_off": _p(NUM, "rise off the contact before closing, so the jaws do not drag on it (ours)",
                           0.003, unit="m"),
            "max_depth": _p(NUM, "how far to descend without a contact before closing anyway (ours)", 0.1,
                            unit="m"),
            "centre_band": _p(NUM, "a contact this close to the hand's axis is under the palm or both jaws: "
                              "close (ours)", 0.012, unit="m"),
            "wrist_to_tcp": _WRIST_TO_TCP,
            "fingertip_reach": _p(NUM, "how far the open fingertips reach beyond the TCP along the hand's z "
                                  "axis, to tell the support under them from the object (the robot's own "
                                  "geometry)", 0.02, unit="m"),
            "max_shift": _p(NUM, "largest move across towards a contact under one jaw (ours)", 0.04, unit="m"),
            "fingertip_extent": _p(VEC, "how far the open fingertips reach sideways from the TCP's axis, along the "
                                   "hand's x and along its y: a hand kept tilted lowers one fingertip's corner that "
                                   "much nearer the support (the robot's own geometry; the Melfa's WRT-102)",
                                   (0.015, 0.044), unit="m", length=2),
            "jaw_half_width": _p(NUM, "half a jaw's width along the jaws' width: a contact under a jaw lies "
                                 "within it, so a move across goes no further that way (the robot's own "
                                 "geometry)", 0.015, unit="m"),
            "max_shifts": _p(INT, "how many times to move across (ours: after a first move of `max_shift`, three "
                             "more bracket the object to within a quarter of it)", 4),
            "hand_extent": _p(VEC, "how far the open hand reaches sideways from the TCP, along the hand's x "
                              "and along its y: its moves stay this far inside the walls of a container the "
                              "task knows (the robot's own geometry; the Melfa's WRT-102)", (0.04, 0.05),
                              unit="m", length=2),
            "search_step": _p(NUM, "spacing of the search along the jaws' width (ours: under a finger's "
                              "width plus the object's)", 0.03, unit="m"),
            "search_points": _p(INT, "points searched after the jaws close on nothing (ours)", 4),
            "locate_along": _p(FLAG, "before closing, sweep along the jaws' width to see where the object's top "
                               "spans with a range sensor along the approach axis, and close on its middle: for a "
                               "place that cannot weigh where the jaws hold it (set by the factory)", False),
            "object_top": _p(NUM, "height (world z) of the object's top as a perceive state saw it, for a task "
                             "that knows no object: set at run time from the value the ATD's <object_top from> "
                             "names; unset = the task's object, or none", unit="m", limits=ranges.COORDINATE),
            "wrist_roll": _p(NUM, "how the last arm joint turns per turn of the hand about the vertical, +1 or -1 "
                                  "(0: none rolls it): the quarter turn off a seen top goes the way that leaves "
                                  "that joint more room (set by the factory)", 0.0, limits=ranges.DIRECTION),
            "filter_time": _FILTER,
        },
    ),
    ControllerSpec(
        "naive_grasp_approach", Role.ARM,
        "Baseline grasp without corrections: from the pregrasp pose, `distance` back along the grasp direction "
        "from where the state begins (the grasp pose the approach planned), move forward until a contact or "
        "`distance`, then stay.",
        "thesis 3.4.1 (naive grasping primitive)",
        {
            "grasp_direction": _p(VEC, "approach direction in the hand frame", (0.0, 0.0, 1.0), length=3,
                                  limits=ranges.DIRECTION),
            "distance": _p(NUM, "how far the pregrasp pose lies back from the grasp pose, and how far to move "
                           "forward from it (thesis: 10 cm)", 0.1, unit="m"),
            "force_threshold": _p(NUM, "contact force on the wrist (ours, as the robust grasp's)", 2.0, unit="N"),
            "velocity": _p(NUM, "forward speed (ours: the robust grasp's approach velocity; at 0.01 the 10 cm "
                           "took half of a grasp state's 20 s)", 0.03, unit="m/s"),
            "filter_time": _FILTER,
        },
    ),
    ControllerSpec(
        "place", Role.ARM,
        "Bring the held object over the target, then descend along -surface_normal until the wrist "
        "feels the surface.",
        "thesis 3.3.3, Eq. 3.4",
        {
            "target": _TARGET,
            "surface_normal": _SURFACE_NORMAL,
            "velocity": _p(NUM, "descent speed (thesis VELOCITY)", 0.005, unit="m/s"),
            "force_threshold": _p(NUM, "surface contact force (thesis FORCE_THRESHOLD)", 5.0, unit="N"),
            "approach_height": _p(NUM, "height above the target where the slow descent starts (ours)", 0.02,
                                  unit="m"),
            "carry_threshold": _p(NUM, "contact force along surface_normal that ends the place while it brings "
                                  "the object over the target: what is under it stands higher than the target "
                                  "(ours: a guarded move's 15 N, over the 5 N the wrist reads as the hand speeds "
                                  "up)", 15.0, unit="N"),
            "max_overshoot": _p(NUM, "how far below the target to keep descending before giving up (ours)",
                                0.03, unit="m"),
            "max_speed": _p(NUM, "TCP speed limit while bringing the object over the target (ours)", 0.15,
                            unit="m/s"),
            "level": _p(FLAG, "turn the hand top-down (keeping its yaw) before descending; off, the hand keeps the "
                              "orientation it starts with: an object grasped from the side goes down as it is held "
                              "(ours)", True),
            "hand_point": _p(VEC, "where the grasp's hand shape holds the object, from the TCP in the hand frame: the "
                                  "target is for the TCP with the object there (ours)", (0.0, 0.0, 0.0), unit="m",
                             length=3),
            "weigh_time": _p(NUM, "how long the arm holds still over the target while the wrist weighs where the "
                                  "object hangs, which then comes down on the target; 0: a wrist that cannot tell, "
                                  "the object taken to be at hand_point (ours)", 0.3, unit="s"),
            "filter_time": _FILTER,
        },
    ),
    ControllerSpec(
        "slide", Role.ARM,
        "Press the object onto the surface with a force between the two thresholds while moving it to "
        "the target.",
        "thesis 3.3.5, Eq. 3.6",
        {
            "target": _TARGET,
            "surface_normal": _SURFACE_NORMAL,
            "lower_force_threshold": _p(NUM, "minimum pressing force (thesis LOWER_FORCE_THRESHOLD)", 5.0,
                                        unit="N"),
            "upper_force_threshold": _p(NUM, "maximum pressing force (thesis UPPER_FORCE_THRESHOLD)", 9.0,
                                        unit="N"),
            "target_velocity": _p(NUM, "speed towards the target (thesis TARGET_VELOCITY)", 0.005, unit="m/s"),
            "contact_velocity": _p(NUM, "speed along the normal (thesis CONTACT_VELOCITY)", 0.005, unit="m/s"),
            "tolerance": _p(NUM, "distance to the target counted as reached (ours): the object stops that much "
                                 "short of its own", 0.001, unit="m"),
            "filter_time": _FILTER,
        },
    ),
    ControllerSpec(
        "release_retreat", Role.ARM,
        "While the hand opens, back away along the surface normal only when the fingers push on "
        "the surface.",
        "thesis 3.3.4, Eq. 3.5",
        {
            "surface_normal": _SURFACE_NORMAL,
            "velocity": _p(NUM, "retreat speed (thesis VELOCITY)", 0.001, unit="m/s"),
            "force_threshold": _p(NUM, "finger-on-surface force (thesis FORCE_THRESHOLD)", 5.0, unit="N"),
            "filter_time": _FILTER,
        },
    ),
    ControllerSpec(
        "explore", Role.ARM,
        "Move the TCP along a direction until the wrist or a pad feels a contact (done; where, written "
        "under `writes`), or until max_distance without one (error).",
        "thesis Table 3.1 (explore)",
        {
            "direction": _p(VEC, "direction of the motion, world frame", required=True, length=3,
                            limits=ranges.DIRECTION),
            **_EXPLORING,
            "max_distance": _p(NUM, "how far to go without a contact before giving up (ours)", 0.3, unit="m"),
            "writes": _p(WORD, "the name the contact (a point) is written under for later states; unset: none"),
            "hand_point": _p(VEC, "the point of the hand that touches, from the TCP in the hand frame: the contact "
                             "written is where it was (the lowest point of the state's hand shape; ours); zeros: "
                             "the TCP", (0.0, 0.0, 0.0), unit="m", length=3),
        },
    ),
    ControllerSpec(
        "perceive", Role.ARM,
        "Choose an object in the container to grasp, by one of thesis 3.4.3's approach-vector generators, "
        "and write its approach (a top-down TCP pose over it) under `writes`, or that nothing was found.",
        "thesis 3.4.3, Fig. 3.26 (random blind, blind exploration, vision)",
        {
            "method": _p(WORD, "the generator: random_blind, blind_exploration or vision", required=True,
                         choices=("random_blind", "blind_exploration", "vision")),
            "writes": _p(WORD, "the name the approach (or nothing found) is written under", required=True),
            "container_pose": _p(VEC, "the container as the task knows it: the frame at the centre of its floor's "
                                 "underside, 4x4 row-major, world frame", required=True, length=16,
                                 limits=ranges.COORDINATE),
            "container_size": _p(VEC, "its outer lengths along its own x y z", required=True, length=3, unit="m",
                                 limits=ranges.SIZE),
            "container_wall": _p(NUM, "the thickness of its walls and floor", 0.01, unit="m"),
            "hand_reach": _p(NUM, "how far the hand reaches below the TCP, pointing down (the robot's own "
                             "geometry: `RobotDescription.hand_reach`)", 0.0, unit="m", limits=ranges.COORDINATE),
            "grasp_reach": _p(NUM, "how far the hand reaches below the TCP, pointing down, in the posture that "
                              "reaches furthest: the approach keeps this clear of the rim, whatever the grasp opens "
                              "the hand to (the robot's own geometry: `RobotDescription.hand_reach`)", 0.0, unit="m",
                              limits=ranges.COORDINATE),
            "hand_radius": _p(NUM, "how far the hand reaches sideways from the TCP: blind exploration's sweep "
                              "keeps the TCP this far in from the walls (the robot's own geometry: "
                              "`RobotDescription.hand_radius`)", 0.05, unit="m"),
            "grasp_extent": _p(VEC, "vision and random blind: how far the open hand reaches sideways along its x "
                               "and along its y (the jaws' closing axis), to turn the jaws where the walls leave them "
                               "room (the robot's own geometry: `RobotDescription.hand_extent`)", (0.04, 0.05),
                               unit="m", length=2),
            "jaw_band": _p(VEC, "vision: the open jaws' fingertips, from how far along the hand's y their pads' "
                           "inner faces stand to how far they reach, and how far they reach along its x: where "
                           "they would come down on what the picture shows, the approach turns and slides to "
                           "keep them off it (the robot's own geometry: `RobotDescription.pad_opening`, "
                           "`hand_extent` within 2 cm); 0 0 0: not known, the turn is the top's alone",
                           (0.0, 0.0, 0.0), unit="m", length=3, limits=ranges.SIZE_OR_NONE),
            "other_tips": _p(VEC, "vision: the rectangle the hand's other lowest links (the SDH2's thumb) cover "
                             "as its pinch comes down, about where it closes: from and to along the hand's x, and "
                             "either way along its y; where they or the fingertips (`jaw_band`) would come down on "
                             "what the picture shows, the approach turns and slides to keep them off it (the robot's "
                             "own geometry: `RobotDescription.low_tips` within 2 cm); 0 0 0: none",
                             (0.0, 0.0, 0.0), unit="m", length=3, limits=ranges.COORDINATE),
            "grasp_footprint": _p(VEC, "vision: the rectangle a hand reaching further one way than the other covers "
                                  "as it comes down to grasp: how far it reaches either way from its middle along the "
                                  "hand's x and y (along `grasp_turn`'s axes), and where that middle lies from the "
                                  "point it grasps at; vision turns "
                                  "the hand, whose half turn then matters, to the way the walls leave it room (the "
                                  "robot's own geometry: `RobotDescription.hand_footprint` of its pinch's preshape, the "
                                  "SDH2's thumb 8.9 cm out); 0 0 0 0: a hand alike either way round (`grasp_extent`)",
                                  (0.0, 0.0, 0.0, 0.0), unit="m", length=4, limits=ranges.COORDINATE),
            "grasp_turn": _p(NUM, "vision: how far the hand turns about its approach axis from the axes "
                             "`grasp_footprint` is given along, whose y is the line its grasp closes along, as vision "
                             "turns jaws across an object's narrow side (the robot's own geometry: "
                             "`RobotDescription.closing_line` of its pinch, to the nearest quarter turn: the "
                             "Barrett's closes along its x, 90); 0: along the hand's y, a parallel jaw's and the "
                             "SDH2's",
                             0.0, unit="deg", limits=ranges.YAW),
            "approach_height": _p(NUM, "the approach puts the hand's lowest point this far over the higher of "
                                  "the object's top and the container's rim (ours)", 0.05, unit="m"),
            **_EXPLORING,
            "sweep_height": _p(NUM, "blind exploration: the hand's lowest point sweeps this far over the floor "
                               "(ours)", 0.02, unit="m"),
            "lane_spacing": _p(NUM, "blind exploration: the sweep's lanes lie at most this far apart (ours: under "
                               "the width of a hand)", 0.05, unit="m"),
            "sweep_extent": _p(VEC, "blind exploration: how far the hand's tip (its links within 2 cm of its lowest "
                               "point) reaches sideways along its x and its y: what meets an object in a sweep, which "
                               "places the object's near side ahead of the TCP (the robot's own geometry: "
                               "`RobotDescription.hand_extent` within 2 cm)", (0.015, 0.01), unit="m", length=2),
            "hand_extent": _p(VEC, "blind exploration: how far the whole hand reaches sideways along its x and its "
                              "y: where the walls' ring cannot come under a lying object's top, the sweep goes along "
                              "each wall at the lanes' height instead, the hand turned so its narrower side faces "
                              "the wall (the robot's own geometry: `RobotDescription.hand_extent`); 0 0: never",
                              (0.0, 0.0), unit="m", length=2, limits=ranges.SIZE_OR_NONE),
            "tip_length": _p(NUM, "blind exploration: how far up from the hand's lowest point its links reach "
                             "sideways no further than its tip (`sweep_extent`): with the tip on a top that far below "
                             "the rim or less, the approach to a top against a wall comes as near it as the tip lets, "
                             "and after its lanes the sweep goes round the walls with the tip alone that far below the "
                             "rim (the robot's own geometry: `RobotDescription.tip_length`); 0: never nearer than "
                             "`hand_radius`", 0.0, unit="m",
                             limits=ranges.SIZE_OR_NONE),
            "spread_tip": _p(FLAG, "blind exploration: the hand's lowest points are fingertips spread apart, none "
                             "under the TCP, so a landing on a top does not place it under the TCP: beside it, "
                             "the hand comes down with its tip's edge over where it landed, on each side, and "
                             "the approach goes the tip's reach towards the likelier side (felt there, else not felt at all; the "
                             "robot's own geometry: the SDH2's stretched fingers, 3.3-4.7 cm off its TCP); off: "
                             "the tip's edge SIDE_STEP past it, to feel how far the top goes on", False),
            "floor_band": _p(NUM, "blind exploration: a contact of the hand's lowest point within this of the "
                             "floor is the floor (ours)", 0.015, unit="m"),
            "camera": _p(WORD, "vision: the depth camera to look with; unset: the robot's first"),
            "floor_margin": _p(NUM, "vision: points less than this over the floor are the floor (ours)", 0.01,
                               unit="m"),
            "wall_margin": _p(NUM, "vision: points less than this in from the walls are the walls (ours)", 0.01,
                              unit="m"),
            "above_rim": _p(NUM, "vision: objects piled up to this far over the rim are still looked for (ours)",
                            0.1, unit="m"),
            "voxel": _p(NUM, "vision: the clustering grid; points more than two voxels apart, with nothing "
                        "between them, are never one object (ours)", 0.01, unit="m"),
            "min_points": _p(INT, "vision: a cluster of fewer points is noise (ours)", 20),
        },
    ),
    ControllerSpec(
        "unscrew_arm", Role.ARM,
        "Arm side of the unscrew: hold while the fingers pinch the cap, twist it about the approach axis through "
        "the grasp centre, pull back to test whether it is free; after a twist or pull that ends early, return "
        "(moved onto the cap's axis by the reactive alignment) to pinch again.",
        "thesis 3.3.6, Fig. 3.11-3.13",
        {
            "grasp_direction": _p(VEC, "the approach axis in the hand frame: the twist turns about it, the pull backs "
                                  "off along it (as the robust grasp's GRASP_DIRECTION)", (0.0, 0.0, 1.0), length=3,
                                  limits=ranges.DIRECTION),
            "twist_angle": _p(NUM, "how far each twist turns the cap (thesis TWIST_ANGLE)", 30.0, unit="deg",
                              limits=ranges.ANGLE),
            "torque_limit": _p(NUM, "a twist stops early above this torque about the approach axis: a collision is "
                               "assumed (thesis UNSCREW_TORQUE_LIMIT)", 10.0, unit="N m"),
            "pull_force_limit": _p(NUM, "a pull stops above this force along the approach: the cap is still on its "
                                   "thread (thesis PULL_FORCE_LIMIT)", 7.0, unit="N"),
            "cap_removed_distance": _p(NUM, "a pull this far with the cap still pinched: the cap is off (thesis "
                                       "CAP_REMOVED_DISTANCE)", 0.04, unit="m"),
            "alignment": _p(FLAG, "the reactive alignment: before each pinch the grasp centre moves onto the cap's "
                            "axis, as the pads' contacts averaged over the last pinch and twist place it "
                            "(thesis 3.3.6, Fig. 3.12); on a gripper, a jaw landed on the cap's top is searched off "
                            "it first (cap_width)", True),
            "max_pinches": _p(INT, "pinches before the unscrew gives up, each followed by a twist unless it closed "
                              "on nothing (ours: a cap of three turns takes 36 twists of 30 degrees)", 40),
            "grasp_centre": _p(VEC, "where the fingers pinch, from the TCP in the hand frame: the twist turns about "
                               "it (the robot's own geometry)", (0.0, 0.0, 0.0), length=3, limits=ranges.COORDINATE),
            "filter_time": _p(NUM, "time constant of the low-pass on the wrist's torque and force (ours: a pad "
                              "slipping on the cap chatters tick to tick)", 0.05, unit="s"),
            "wrist_turn": _p(NUM, "how the last arm joint turns with the hand about the approach axis, +1 or -1 "
                             "(0: no joint named): a twist goes no further than that joint can still turn "
                             "(the robot's own geometry)", 0.0, limits=ranges.DIRECTION),
            "cap_width": _p(NUM, "how wide the cap is, for a gripper's jaws to find room around it: a guarded descent "
                            "that stopped short of its target had a jaw land on the cap's top, and with the "
                            "alignment the jaws search across, their room around the cap apart, and descend again "
                            "(the task's object_size; 0: no such descent, as a multi-finger pinch)", 0.0, unit="m",
                            limits=ranges.SIZE_OR_NONE),
            "force_threshold": _p(NUM, "contact force on the wrist that is a jaw on the cap's top (as the guarded "
                                  "descent's it repeats: a jaw brushing the cap's side on its way down presses 2-5 N)",
                                  15.0, unit="N"),
        },
    ),
)

_HAND_CONTROLLERS = (
    ControllerSpec("hold_position", Role.HAND,
                   "Keep the finger joints where they were when the state began.", "D5 2.2.4 (hand idle)"),
    ControllerSpec(
        "hand_shape", Role.HAND, "Drive the fingers to a named shape of this hand.", "D5 2.2.2 hand shapes",
        {"shape": _p(WORD, "an ATD hand shape this hand can make, or a posture of its own the factory names "
                             "(a three-finger hand's `push`)", required=True),
         "speed": _p(NUM, "fraction of the joints' speed limit to use (ours)", 0.5, limits=ranges.SPEED_FRACTION)},
    ),
    ControllerSpec(
        "robust_grasp_hand", Role.HAND,
        "Hand side of the robust grasp: preshape, close when the arm reports contact, redo the grasp "
        "when a finger loses contact or the fingers stop unevenly, then raise the finger force; a pinch "
        "then lifts the object a little and grasps it again across its centre of mass when the wrist feels "
        "its weight hang off the pinch line.",
        "thesis 3.3.1 (finger-lost correction, force adaptation); D5 3.3 (finger-extension criterion)",
        {
            "preshape": _p(WORD, "starting hand configuration (thesis PREGRASP_TYPE); unset = current"),
            "pregrasp_size": _p(NUM, "hand opening before closing, 0..1 (thesis PREGRASP_SIZE); unset = current"),
            "grasp_shape": _p(WORD, "the grasp to close into", required=True),
            "grasp_force": _p(NUM, "fingertip force after force adaptation (ours)", 5.0, unit="N"),
            "contact_threshold": _p(NUM, "pad force counted as finger contact (ours)", 0.3, unit="N"),
            "finger_lost_correction": _p(FLAG, "reopen and shift when a finger misses (thesis 3.3.1)", True),
            "finger_lost_shift": _p(NUM, "shift towards the fingers that touched, per finger-lost correction (ours; "
                                    "D5 moves 5 cm, the Barrett's distance between fingers)", 0.015, unit="m"),
            "object_lost_step": _p(NUM, "step along the approach when no finger touched (D5's security reflex: "
                                   "'a little bit down')", 0.01, unit="m"),
            "search_step": _p(NUM, "step across the pinch line when two pinching fingers touched nothing: one "
                              "side, then the other (ours)", 0.025, unit="m"),
            "extension_correction": _p(FLAG, "D5 3.3.3: with every finger on the object, reopen and move the hand "
                                       "(position correction Z, orientation correction alpha) while the grasp "
                                       "is unstable by the finger-extension criterion", True),
            "side_edge_correction": _p(FLAG, "with both pinching pads pressing the object with their side edges "
                                       "only, on one side of the pinch line, reopen and move across to where they "
                                       "pressed (ours; the factory's hand says where: docs/robust-grasp.md)", False),
            "closing_swing": _p(NUM, "how much further the hand reaches along the approach on its way from the "
                                "preshape to the grasp: told to close on a ball with a grasping pad on the table, it "
                                "first rises this far (the robot's own geometry; 0: it never does)", 0.0, unit="m",
                                limits=ranges.SIZE_OR_NONE),
            "stable_quality": _p(NUM, "D5's bound on the finger-extension quality Q (Eq. 3.1) of a stable grasp, "
                                 "extensions in units of the preshape's reach (D5: 0.01)", 0.01),
            "alpha_threshold": _p(NUM, "the least orientation correction alpha (Eq. 3.2) made (D5: 0.01 rad)",
                                  0.573, unit="deg", limits=ranges.ANGLE),
        },
    ),
    ControllerSpec(
        "naive_grasp_hand", Role.HAND,
        "Baseline grasp without corrections: once the arm has stopped, close, stopping each finger that "
        "touches, then squeeze slightly; done once two pads (a gripper: its motor) feel the object, an error "
        "otherwise.",
        "thesis 3.4.1 (naive grasping primitive)",
        {
            "preshape": _p(WORD, "starting hand configuration; unset = current"),
            "pregrasp_size": _p(NUM, "hand opening before closing, 0..1, as the robust grasp's (multi-finger "
                                "hands); unset = the preshape's"),
            "grasp_shape": _p(WORD, "the grasp to close into (multi-finger hands; a gripper just closes)"),
            "contact_threshold": _p(NUM, "pad force counted as finger contact (ours)", 0.3, unit="N"),
            "squeeze": _p(NUM, "effort added at the end, fraction of each finger's effort limit (ours: at 0.1 the "
                          "PyBullet Barrett's pads pressed a cylinder with 0 and 0.5 N, under the 1 N its "
                          "grasp_stable asks, and the grasp waited out its timeout)", 0.3),
            "grasp_force": _p(NUM, "a gripper's grip force once both jaws touch, in place of the squeeze: the "
                              "robust grasp's, so that the baseline lacks only the corrections (ours)", unit="N"),
        },
    ),
    ControllerSpec(
        "close_until_force", Role.HAND,
        "Close the jaws until the grip force reaches grasp_force (or, the squeeze at its +50 % limit, 70 % of it on "
        "the weaker pad: a tilted grip loads one pad more), then keep it.",
        "thesis 7.3 (Melfa grasp)",
        {
            "grasp_force": _p(NUM, "grip force to reach", 15.0, unit="N"),
            "closing_speed": _p(NUM, "jaw closing speed (ours: at 0.02 a close took 1.7 s of each step of the "
                                 "robust grasp's search, and the grasp's timeout cut the search short)", 0.04, unit="m/s"),
            "force_source": _FORCE_SOURCE,
            "max_recentre": _p(NUM, "how far the arm follows a contact off the pads' middle along the jaws' "
                               "width before the jaws close anyway: a contact on the pad lies within this of "
                               "its middle, so one that stays off-centre moves with the pad (ours: about a "
                               "pad's half width)", 0.01, unit="m"),
        },
    ),
    ControllerSpec(
        "squeeze", Role.HAND, "Keep applying the grip force so the object does not loosen while it moves.",
        "thesis 7.3 (Melfa transport)",
        {"grasp_force": _p(NUM, "grip force to hold", 15.0, unit="N"), "force_source": _FORCE_SOURCE},
    ),
    ControllerSpec(
        "open_to", Role.HAND, "Open the hand until it reaches the hand position.",
        "thesis 3.3.4 HAND_TARGET_POSITION; thesis 7.3 (Melfa release)",
        {"hand_position": _p(NUM, "target opening, 0 = closed .. 1 = open (thesis default 1.0)", 1.0),
         "speed": _p(NUM, "fraction of the joints' speed limit to use (ours)", 0.5, limits=ranges.SPEED_FRACTION)},
    ),
    ControllerSpec(
        "unscrew_hand", Role.HAND,
        "Hand side of the unscrew: pinch the cap until each grasping pad presses the grasp force, keep pressing "
        "(closing on when contact is lost) through the twist and the pull, tell the arm when the pads closed on "
        "nothing and where the contacts put the cap's axis; open when the arm asks.",
        "thesis 3.3.6 (pinch, FINGER_GRASPING_FORCE, FINGER_MIN_DISTANCE, reactive alignment)",
        {
            "preshape": _p(WORD, "starting hand configuration; unset = current"),
            "pregrasp_size": _p(NUM, "hand opening before closing, 0..1; unset = the preshape's"),
            "grasp_shape": _p(WORD, "the grasp to close into: two fingers pinch (thesis GRASPING_FINGERS 2)",
                              required=True),
            "grasp_force": _p(NUM, "force each grasping pad presses the cap with (thesis FINGER_GRASPING_FORCE)", 5.0,
                              unit="N"),
            "contact_threshold": _p(NUM, "pad force counted as finger contact (ours)", 0.3, unit="N"),
            "finger_min_distance": _p(NUM, "pads closer than this hold nothing (thesis FINGER_MIN_DISTANCE)", 0.012,
                                      unit="m"),
            "cap_width": _p(NUM, "the cap's believed width (the task's object_size); unset = not known", unit="m"),
            "pad_reach": _p(NUM, "how far past the TCP, along the approach, the grasping pads' lower edge reaches "
                                 "where they come cap_width apart (the arm started the pinch there): pads that rise "
                                 "as they close nearer, on a narrower cap, are followed down by the arm; unset = no "
                                 "following", unit="m", limits=ranges.COORDINATE),
        },
    ),
    ControllerSpec(
        "unscrew_jaws", Role.HAND,
        "Hand side of the unscrew on a parallel gripper: grip the cap as the gripper's grasp does (close when the "
        "arm says, centre on the pads' contacts, press with the grasp force), keep pressing through the wrist's "
        "twist and the pull, tell the arm when the jaws closed on nothing and where the pads' contacts put the "
        "cap's axis; open when the arm asks.",
        "thesis 3.3.6 mapped on a gripper (FINGER_GRASPING_FORCE, FINGER_MIN_DISTANCE, reactive alignment); "
        "thesis 7.3 (Melfa grasp)",
        {
            "grasp_force": _p(NUM, "grip force on the cap (thesis FINGER_GRASPING_FORCE)", 5.0, unit="N"),
            "closing_speed": _p(NUM, "jaw closing speed (the gripper's grasp's)", 0.04, unit="m/s"),
            "force_source": _FORCE_SOURCE,
            "max_recentre": _p(NUM, "how far the arm follows a contact off the pads' middle before the jaws close "
                               "anyway (the gripper's grasp's)", 0.01, unit="m"),
            "finger_min_distance": _p(NUM, "jaws closer than this hold nothing (thesis FINGER_MIN_DISTANCE)", 0.012,
                                      unit="m"),
        },
    ),
)

_TACTILE_PARAMS = {
    "force_threshold": _p(NUM, "pad force counted as touching", 0.5, unit="N"),
    "min_pads": _p(INT, "how many pads must touch", 1, limits=ranges.PADS),
    "for_time": _FOR,
}

CREEP_WATCH = 6.0  # s a grip that may creep out is watched before it counts as held: three times a transport's 2 s hold
SLIP_DISTANCE = 0.001  # m a pad's centre of pressure may move and count as still: a contact crossing into the next taxel (3.3-4.8 mm) moved it 1.5-1.7 mm

_CONDITIONS = (
    ConditionSpec("arm_done", "The state's arm controller reports it has finished.",
                  params={"for_time": _p(NUM, "the arm must have been finished this long (ours; 0 = at once)",
                                         0.0, unit="s")}),
    ConditionSpec("hand_done", "The state's hand controller reports it has finished."),
    ConditionSpec("arm_error", "The arm controller gave up (target unreachable, no contact within reach)."),
    ConditionSpec("hand_error", "The hand controller gave up (nothing between the fingers, shape unreachable)."),
    ConditionSpec("arm_fault", "Arm hardware failure: joint limit, actuator saturation or tracking error."),
    ConditionSpec("hand_fault", "Hand hardware failure: joint limit, actuator saturation or tracking error."),
    ConditionSpec("simulation_unstable", "The physics engine diverged (non-finite or runaway state)."),
    ConditionSpec("timeout", "Time since the state began.",
                  params={"seconds": _p(NUM, "time limit", unit="s", required=True, limits=ranges.TIMEOUT)}),
    ConditionSpec("subtask_succeeded", "The sub-task's machine ended in a success state."),
    ConditionSpec("subtask_failed", "The sub-task's machine ended in a failure state."),
    ConditionSpec("subtask_ended_in", "The sub-task's machine ended in the end state named (an ATD <outcome>).",
                  params={"end_state": _p(WORD, "the sub-task's end state", required=True)}),
    ConditionSpec("tactile_force_above", "At least min_pads pads read >= force_threshold.",
                  SensorKind.TACTILE, _TACTILE_PARAMS),
    ConditionSpec("tactile_force_below", "Fewer than min_pads pads read >= force_threshold.",
                  SensorKind.TACTILE, _TACTILE_PARAMS),
    ConditionSpec(
        "tactile_load_change",
        "The summed pad force moved by more than force_change since the state began: the held object "
        "touched something.", SensorKind.TACTILE,
        {"force_change": _p(NUM, "change of the summed pad force", 1.0, unit="N"), "for_time": _FOR},
    ),
    ConditionSpec(
        "load_held",
        "The wrist carries at least `weight` more than the empty hand did as the latest grasp began: the "
        "object is held, once it has left its support.", SensorKind.FORCE_TORQUE,
        {
            "weight": _p(NUM, "least load that counts as the object (ours: half the task's object weight)", 0.02,
                         unit="kg"),
            "filter_time": _p(NUM, "time constant of the low-pass on the load: a hand speeding up reads as load "
                              "too (ours)", 0.05, unit="s"),
            "for_time": _FOR,
        },
    ),
    ConditionSpec(
        "fingers_pressing",
        "A closing joint of the hand presses on something (its effort in the closing direction) more open "
        "than the hand's `posture`: something stands between the fingers.",
        params={
            "effort": _p(NUM, "least closing effort that counts as pressing, as a fraction of the joint's effort "
                         "limit (ours: as a hold keeps a pressing finger's effort)", 0.05),
            "posture": _p(WORD, "the hand posture the fingers were closing to (one the robot's hand makes)",
                          required=True),
            "for_time": _FOR,
        },
    ),
    ConditionSpec(
        "fingers_still",
        "The hand's closing joints have stopped moving: a grip that keeps closing (or opening) while it "
        "holds is squeezing the object out or letting it slip, so the object is not yet held still.",
        params={
            "drift": _p(NUM, "largest filtered speed of a closing joint that counts as still, as a fraction of "
                        "the joint's travel per second (ours: 1%; the Melfa's config asks 3%, 1 mm/s on its 34 mm "
                        "jaws)", 0.01,
                        unit="1/s"),
            "filter_time": _p(NUM, "time constant of the low-pass on the joint positions whose lag gives the "
                              "speed, and the window over which their spread gives it too: a force-controlled grip "
                              "chatters by a few mm/s about a still mean (ours)", 0.5,
                              unit="s"),
            "for_time": _p(NUM, "how long the fingers must stay still (ours)", 0.2, unit="s"),
        },
    ),
    ConditionSpec(
        "slip_watched",
        "The pads' contacts have not moved more than `distance` across them while the arm holds at its target, or "
        "have been watched `watch` since they first did: contacts travelling across a pad while the hand holds still "
        "may be the object turning or sliding out of the grip, which then drops it within the watch. Reads the pads' "
        "taxel arrays; a pad without one is not read.", SensorKind.TACTILE,
        {
            "distance": _p(NUM, "how far a pad's centre of pressure may move over the arm's hold and count as still "
                           "(ours)", SLIP_DISTANCE, unit="m"),
            "watch": _p(NUM, "how long a grip whose contacts moved is held before it counts as stable: three times a "
                        "transport's 2 s hold (ours)", CREEP_WATCH, unit="s"),
        },
    ),
    ConditionSpec(
        "wrist_force_above", "The tared, filtered wrench exceeds the threshold.", SensorKind.FORCE_TORQUE,
        {
            "force_threshold": _p(NUM, "force limit", 15.0, unit="N"),
            "axis": _p(WORD, "which force: the norm, or minus the hand z force (pushed back)", "norm",
                       choices=("norm", "-z")),
            "filter_time": _FILTER,
            "for_time": _FOR,
        },
    ),
    ConditionSpec("gripper_force_above", "The gripper motor force is at least the threshold.", SensorKind.GRIPPER,
                  {"force_threshold": _p(NUM, "motor force", 5.0, unit="N"), "for_time": _FOR}),
    ConditionSpec("gripper_force_below", "The gripper motor force is below the threshold.", SensorKind.GRIPPER,
                  {"force_threshold": _p(NUM, "motor force", 5.0, unit="N"), "for_time": _FOR}),
    ConditionSpec("gripper_opening_above", "The jaws are open wider than the width.", SensorKind.GRIPPER,
                  {"width": _p(NUM, "jaw opening", 0.005, unit="m"), "for_time": _FOR}),
    ConditionSpec("gripper_opening_below", "The jaws are open less than the width.", SensorKind.GRIPPER,
                  {"width": _p(NUM, "jaw opening", 0.005, unit="m"), "for_time": _FOR}),
    ConditionSpec("range_below", "The range sensor reads less than the distance.", SensorKind.RANGE,
                  {"distance": _p(NUM, "range", 0.05, unit="m"), "for_time": _FOR}),
    ConditionSpec("range_above", "The range sensor reads more than the distance.", SensorKind.RANGE,
                  {"distance": _p(NUM, "range", 0.05, unit="m"), "for_time": _FOR}),
    ConditionSpec("object_found", "The state's perceive controller has finished and written an approach under "
                  "`value`.", params={"value": _p(WORD, "the name the perceive state writes", required=True)}),
    ConditionSpec("nothing_found", "The state's perceive controller has finished and found nothing; it wrote "
                  "so under `value`.", params={"value": _p(WORD, "the name the perceive state writes",
                                                           required=True)}),
)

ARM_CONTROLLERS: Mapping[str, ControllerSpec] = MappingProxyType({c.name: c for c in _ARM_CONTROLLERS})
HAND_CONTROLLERS: Mapping[str, ControllerSpec] = MappingProxyType({c.name: c for c in _HAND_CONTROLLERS})
CONTROLLERS: Mapping[str, ControllerSpec] = MappingProxyType({**ARM_CONTROLLERS, **HAND_CONTROLLERS})
CONDITIONS: Mapping[str, ConditionSpec] = MappingProxyType({c.kind: c for c in _CONDITIONS})


# --- parameter values: one text form for XML and config files --------------------------------


def format_number(value: float) -> str:
    """Fixed, locale-free float text: 9 significant digits, no '-0'."""
    text = f"{float(value):.9g}"
    return "0" if text == "-0" else text


def format_value(value: ParamValue) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return str(value) if isinstance(value, int) else format_number(value)
    if isinstance(value, str):
        return value
    if value and isinstance(value[0], tuple):
        return "; ".join(" ".join(format_number(v) for v in point) for point in value)
    return " ".join(format_number(v) for v in value)


def parse_value(spec: ParamSpec, text: str) -> ParamValue:
    """Read a parameter's text; raise ValueError with a reason a person can act on."""
    text = text.strip()
    if spec.type is ParamType.FLAG:
        if text.lower() not in ("true", "false"):
            raise ValueError(f"'{text}' is not true or false")
        return text.lower() == "true"
    if spec.type is ParamType.WORD:
        return coerce_value(spec, text)
    if spec.type is ParamType.POINTS:
        points = [p for p in text.split(";") if p.strip()]
        return coerce_value(spec, tuple(ranges.numbers(p.split()) for p in points))
    if spec.type is ParamType.VECTOR:
        return coerce_value(spec, ranges.numbers(text.split()))
    try:
        value = ranges.integer(text) if spec.type is ParamType.INTEGER else ranges.numbers([text])[0]
    except ValueError:
        raise ValueError(f"'{text}' is not {spec.type.with_article}") from None
    return coerce_value(spec, value)


def coerce_value(spec: ParamSpec, value: object) -> ParamValue:
    """Check a value against its spec and return it in its canonical Python type."""
    kind = spec.type
    if kind is ParamType.FLAG and isinstance(value, bool):
        return value
    if kind is ParamType.INTEGER and isinstance(value, int) and not isinstance(value, bool):
        return _in_range(spec, value)
    if kind is ParamType.NUMBER and isinstance(value, (int, float)) and not isinstance(value, bool):
        return float(_in_range(spec, value))
    if kind is ParamType.WORD and isinstance(value, str):
        if spec.choices and value not in spec.choices:
            raise ValueError(f"'{value}' is not one of {', '.join(spec.choices)}")
        return value
    if kind is ParamType.VECTOR and isinstance(value, (tuple, list)):
        if spec.length is not None and len(value) != spec.length:
            raise ValueError(f"needs {spec.length} numbers, got {len(value)}")
        return tuple(_number_in_range(spec, v) for v in value)
    if kind is ParamType.POINTS and isinstance(value, (tuple, list)):
        if any(not isinstance(p, (tuple, list)) or len(p) != 3 for p in value):
            raise ValueError("every point needs 3 numbers (x y z)")
        return tuple(tuple(_number_in_range(spec, v) for v in p) for p in value)
    raise ValueError(f"{value!r} is not {kind.with_article}")


def _in_range(spec: ParamSpec, value: float) -> float:
    problem = spec.allowed.problem(value)
    if problem:
        raise ValueError(problem)
    return value


def _number_in_range(spec: ParamSpec, value: object) -> float:
    """One number of a vector or of points, checked before it becomes a float (which a
    400-digit integer from a TOML file would overflow)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(f"{value!r} is not a number")
    return float(_in_range(spec, value))


def check_params(where: str, specs: Mapping[str, ParamSpec], params: Mapping[str, object],
                 at_run_time: frozenset[str] = frozenset()) -> list[str]:
    """Problems with a parameter set: unknown names, missing required ones (but those the run
    supplies, `at_run_time`: a target read from a named value), wrong types."""
    problems = [f"{where}: unknown parameter '{name}'" for name in params if name not in specs]
    problems += [f"{where}: missing required parameter '{name}'"
                 for name, spec in specs.items() if spec.required and name not in params and name not in at_run_time]
    for name, value in params.items():
        if name in specs:
            try:
                coerce_value(specs[name], value)
            except ValueError as exc:
                problems.append(f"{where}: parameter '{name}': {exc}")
    return problems


def defaults(specs: Mapping[str, ParamSpec]) -> dict[str, ParamValue]:
    """The default of every parameter that has one (empty point lists are left out)."""
    return {name: spec.default for name, spec in specs.items() if spec.default not in (None, ())}
