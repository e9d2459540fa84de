"""The factory interface: what the generic translator asks of each robot (thesis Fig. 7.3b).

A factory knows one robot: its arms, hands, sensors and physical description, and how each abstract
primitive and abstract event becomes concrete controllers and conditions on it. It is
asked about one node or one event at a time, with the task's object and environment
information (thesis 7.2.2), and answers with vocabulary from `atd.model.controllers`.
When it cannot, it raises `Unmappable` with the reason; the translator turns that into
a diagnostic with the ATD file:line.

The generic parts every robot shares live here: hand-shape fallback, motion targets
from the object information, the reach check, and the events any robot detects the
same way (timeout, success, error, hardware failure).
"""

from __future__ import annotations

import copy
from abc import ABC, abstractmethod
from dataclasses import dataclass, field, replace
from functools import cached_property
from pathlib import Path
from typing import ClassVar, Mapping

import numpy as np

from atd.model.controllers import CONDITIONS, CONTROLLERS, ParamValue, SensorKind, defaults
from atd.model.estd import Condition, ConditionGroup, Controller
from atd.model.frames import GRAVITY, rotation_rpy, rpy_of
from atd.model.ranges import FORCE, WEIGHT
from atd.model.resolved_rate import TURN_MARGIN
from atd.model.validate import value_kinds
from atd.model.task import Environment, ObjectInfo, State, Task, Transition, Vec3
from atd.model.vocabulary import (FIRED_BY, PERCEPTUAL_PRIMITIVES, EventType, HandShape, Movement, PathPoint,
                                  PerceptionMethod, StateType, ValueKind)
from factories.beside import description_module, shipped_config
from factories.config import RobotConfig, load_config
from factories.description import RobotDescription
from factories.reach import Reach
from factories.robot_info import robot_info
from factories.grasp_turn import grasp_turn
from factories.turns import KEEPING, arriving, grasp_ahead, leads_into, target_turn, turn_at_start
from primitives.robot import RobotInfo

ConditionNode = Condition | ConditionGroup

GRASPS = ("robust", "naive")  # what a factory may be told to grasp with
APPROACH_CLEARANCE = 0.10  # m above the object's top: where a free approach ends
LIFT_HEIGHT = 0.10  # m: a transport without a path lifts the object this much
# m of room a hand at the object must keep from every obstacle: the arm ends its moves
# within 3 mm of the target, and fingers coming down spread sway by a few more; the SDH2's
# thumb, 4 mm clear of a wall on paper, landed on it (empty_the_box.xml, both engines).
HAND_CLEARANCE = 0.01
# m from its target within which a contact ends a move carrying the object as arrived: a
# transport only at its target, a place where the object's underside meets the surface
# the task puts it on (the target is the object resting there; ours).
CARRIED_MARGIN = {StateType.TRANSPORT: 0.0, StateType.PLACE: 0.01}
# s a transport holds the object at its target before it succeeds (thesis 3.4.1: the object lifted
# "does not move in the hand"; the drops it catches: docs/constants.md)
HELD_FOR = 2.0
# m above the hand's lowest point that its sweeping tip spans: a blind exploration sweeps 2 cm
# over the floor and every library object stands 3.8 cm or more whichever way it lies, so only
# links this low meet it (the Melfa's fingers, not the gripper body 6 cm above them)
SWEEPING_TIP = 0.02
# rad: a quarter turn either way closes a gripper alike; the hand turns this much short of it, the
# way the arm reaches, so a move's shorter turn (`turn_to_yaw`) goes that way whatever the noise in
# the hand's heading
TIE_SHORT = np.radians(1.0)
TURN_TOLERANCE = np.radians(1.0)  # rad: a turn to the object under a degree changes no grasp; the hand keeps its yaw
WRIST_ALIGNED = 0.99  # cos: a last joint within 8 degrees of the approach axis rolls the hand about it (ours)
# m a hand in a posture that stands in to fit a box (`Hand.boxed`) is kept further off its walls
# than it reaches: the arm reaches an approach to within 3 mm, and the Barrett's boxed pinch, its
# fingers widest at the rim's height, came down on the rim 1.4 mm over it and closed 1 cm over a block
BOXED_CLEARANCE = 0.005
ALONG_Y = np.radians(10.0)  # rad: a pinch closing this near a quarter turn of the hand's y is turned by vision
PRESSING_FOR = 0.1  # s a finger presses short of its posture before a look's give-up counts as a grip


class Unmappable(Exception):
    """The robot cannot do what the node or event asks; `reason` says why, `hint` what to do."""

    def __init__(self, reason: str, hint: str | None = None) -> None:
        super().__init__(reason)
        self.reason = reason
        self.hint = hint


@dataclass(frozen=True)
class Sensor:
    name: str
    """What conditions and the ESTD call it; a tactile sensor is named as its `FingerPad`."""
    kind: SensorKind
    """force_torque, tactile, joints or range: which conditions can read it."""
    description: str
    """One line for `atd robots list` and `show`."""


@dataclass(frozen=True)
class Hand:
    name: str
    """The hand's model name, as users know it."""
    kind: str
    """'multi-finger' or 'parallel jaw', shown by `atd robots`."""
    shapes: frozenset[HandShape]
    """The D5 hand shapes it can make."""
    closest: Mapping[HandShape, HandShape]
    """Every other shape -> the closest it can make (translation warns when it falls back)."""
    max_opening: float
    """m between the fingertips, fully open."""
    cannot_grasp: Mapping[HandShape, str] = field(default_factory=dict)
    """Grasp shapes it must refuse -> why (a translation that asks for one fails with that reason)."""


@dataclass(frozen=True)
class Arm:
    """One arm of the robot with its hand and sensors: what `--arm` chooses."""

    name: str
    """What `--arm` chooses."""
    description: str
    """One line for `atd robots show`."""
    hand: Hand
    """Its hand's capabilities."""
    sensors: tuple[Sensor, ...]
    """Every sensor on this arm and hand."""

    def sensors_of(self, kind: SensorKind) -> tuple[str, ...]:
        return tuple(s.name for s in self.sensors if s.kind is kind)


@dataclass(frozen=True)
class Capabilities:
    primitives: frozenset[StateType]
    """The ATD primitives it maps."""
    hand_shapes: frozenset[HandShape]
    """The hand shapes its arm's hand makes."""
    events: frozenset[EventType]
    """The abstract events it can detect."""


@dataclass(frozen=True)
class MappingRow:
    """One row of a robot's mapping table, in the columns of thesis Tables 7.3 and 7.4."""

    abstract: str
    """The ATD primitive."""
    concrete: str
    """The robot's primitive for it; '-' when it has none."""
    extra_parameters: str
    """What the concrete primitive needs beyond the ATD."""
    control_and_sensors: str
    """The controllers and sensors it uses."""


@dataclass(frozen=True)
class MappingContext:
    """What the factory may know beyond the node or event itself (thesis 7.2.2).

    A sub-task runs in the world of the task around it: `surroundings` holds that task's
    environment (the walls of the box a pick-one round reaches into), which the sub-task's
    own file need not repeat."""

    task: Task
    """The task being translated: its objects and environment."""
    surroundings: Environment | None = None
    """The environment of the task around a sub-task, or None."""
    acting: str | None = None
    """The object the node or the origin of the edge acts on (`object="..."`); None: the task's first."""

    def acting_on(self, name: str | None) -> MappingContext:
        """This context for a node or edge that acts on the object called `name` (None: the first)."""
        return self if name == self.acting else replace(self, acting=name)

    @property
    def object(self) -> ObjectInfo | None:
        """The object the node or edge acts on: the one it names, or the task's first."""
        return self.task.objects[self.acting] if self.acting else self.task.object

    @property
    def environment(self) -> Environment | None:
        own = self.task.environment
        if self.surroundings is None or own is None:
            return own or self.surroundings
        return Environment(obstacles=self.surroundings.obstacles + own.obstacles,
                           containers=self.surroundings.containers + own.containers)

    def state(self, name: str) -> State:
        return self.task.states_by_name[name]


@dataclass(frozen=True)
class NodeMapping:
    """The concrete primitive for one ATD node; `notes` become warnings (e.g. shape fallbacks)."""

    primitive: str
    """The concrete primitive's name, written in the ESTD."""
    arm: Controller
    """The arm controller."""
    hand: Controller
    """The hand controller."""
    notes: tuple[str, ...] = ()
    """Warnings for the user (a hand-shape fallback)."""


# What every factory's mapping table says of the perceptual primitives (docs/perception.md).
PERCEPTION_ROWS = (
    MappingRow("explore", "explore", "direction, contact force", "arm control, FT and tactile sensors"),
    MappingRow("perceive", "perceive", "container, hand reach and radius",
               "depth camera (vision), FT and tactile sensors (blind exploration)"),
)


class Factory(ABC):
    """Base of every robot factory. Subclasses set the class attributes and the mapping."""

    name: ClassVar[str]
    description: ClassVar[str]
    arms: ClassVar[tuple[Arm, ...]]  # the first is the default
    primitives: ClassVar[frozenset[StateType]]
    node_table: ClassVar[tuple[MappingRow, ...]]  # thesis Tables 7.3 / 7.4 columns
    # Primitives its kind would map that this robot leaves out: why ("{name}": the robot's), and what instead.
    lacks: ClassVar[dict[StateType, tuple[str, str]]] = {}

    def __init__(self, arm: str | None = None, config: Path | None = None, grasp: str = "robust") -> None:
        if grasp not in GRASPS:
            raise ValueError(f"grasp must be one of: {', '.join(GRASPS)}; got '{grasp}'")
        self.grasp = grasp
        names = [a.name for a in self.arms]
        if arm is not None and arm not in names:
            raise ValueError(f"robot '{self.name}' has no arm '{arm}'; choose one of: {', '.join(names)}")
        self.arm = self.arms[names.index(arm)] if arm else self.arms[0]
        shipped = shipped_config(type(self))
        self.config = load_config(shipped, self.name) if shipped else RobotConfig()
        if config is not None:
            self.config = load_config(config, self.name).over(self.config)

    def on_arm(self, name: str) -> Factory:
        """This factory, with its config and grasp, for another of the robot's arms: a task
        that names roles maps each state on the arm its role is bound to."""
        if name == self.arm.name:
            return self
        names = [a.name for a in self.arms]
        if name not in names:
            raise ValueError(f"robot '{self.name}' has no arm '{name}'; choose one of: {', '.join(names)}")
        other = copy.copy(self)
        per_arm = {k for klass in type(self).__mro__ for k, v in vars(klass).items() if isinstance(v, cached_property)}
        other.__dict__ = {k: v for k, v in self.__dict__.items() if k not in per_arm}
        other.arm = self.arms[names.index(name)]
        return other

    # -- what the robot is ----------------------------------------------------------------
    @property
    def capabilities(self) -> Capabilities:
        """What it maps. Of the events only some states fire, those whose states it maps; a
        sub-task's outcome is the executor's, every robot's."""
        events = frozenset(e for e in EventType if e not in self.undetectable_events
                           and (e not in FIRED_BY or FIRED_BY[e] & (self.primitives | {StateType.TASK})))
        return Capabilities(self.primitives, self.arm.hand.shapes, events)

    undetectable_events: ClassVar[tuple[EventType, ...]] = ()

    # -- the two questions the translator asks --------------------------------------------
    def map_state(self, state: State, context: MappingContext) -> NodeMapping:
        """What the translator asks for a node: the robot's own mapping (`map_node`), except
        that a factory made with grasp="naive" maps every grasp to the naive grasp of thesis
        3.4.1 (and every unscrew to one without its reactive alignment), the baseline the robust grasp is measured by (same hand shape, opening and
        checks, the wrist's contact felt the same, and on a gripper the same grip force: with
        10% of the Baxter's 20 N it never reached the 8 N its grasp_stable asks, and never
        lifted). A primitive the robot `lacks` is refused with its own reason."""
        if state.type in self.lacks:
            why, instead = self.lacks[state.type]
            raise Unmappable(why.format(name=self.name), instead)
        if state.type in PERCEPTUAL_PRIMITIVES - self.primitives:
            raise Unmappable(f"the {self.name} has no {state.type.value} primitive: no controller of its runs "
                             f"'{state.type.value}' yet", "translate the task for a robot that lists it "
                             "(`atd robots list`: primitives)")
        if state.type in PERCEPTUAL_PRIMITIVES:
            return self.perceptual(state, context)
        if state.type is StateType.UNSCREW and StateType.UNSCREW not in self.primitives:
            raise Unmappable(f"the {self.name} has no unscrew primitive: unscrewing pinches the cap between two "
                             "fingertips or grips it in a gripper's jaws, and turns it (thesis 3.3.6), and the "
                             f"{self.arm.hand.name} does neither",
                             "translate the task for a robot that lists it (`atd robots list`: primitives)")
        mapping = self.map_node(state, context)
        if self.grasp == "naive" and state.type is StateType.UNSCREW:
            # The unscrew's naive form is the thesis's "reactive: no" (Table 3.4): no alignment
            # onto the cap's axis between pinches; an ATD's own `alignment` parameter still wins.
            arm = mapping.arm.model_copy(update={"params": {**mapping.arm.params, "alignment": False}})
            return replace(mapping, arm=arm)
        if self.grasp != "naive" or state.type is not StateType.GRASP:
            return mapping
        hand, arm = mapping.hand.params, mapping.arm.params
        # A gripper's grasp names its grip force; a multi-finger naive grasp keeps its squeeze.
        grip = hand.get("grasp_force") if mapping.hand.name == "close_until_force" else None
        # The wrist's contact as the robust grasp feels it: the Baxter's virtual wrench is too
        # noisy for 2 N unfiltered, and its naive approach stopped 1 cm from the pregrasp pose.
        feel = {"force_threshold": arm.get("force_threshold"), "filter_time": arm.get("filter_time")}
        return NodeMapping("naive grasp", self.controller("naive_grasp_approach", **feel),
                           self.controller("naive_grasp_hand", preshape=hand.get("preshape"),
                                           grasp_shape=hand.get("grasp_shape"),
                                           pregrasp_size=hand.get("pregrasp_size"), grasp_force=grip),
                           mapping.notes)

    def perceptual(self, state: State, context: MappingContext) -> NodeMapping:
        """explore and perceive: the same controllers on every robot (docs/perception.md),
        given this robot's own geometry; refused where the robot cannot do what they need."""
        if state.type is StateType.EXPLORE:
            touching = self.acting_point(state, touching=True)
            # No lighter than this robot's own explore threshold: what its wrist tells from its own jolts.
            least = float(self.config.controllers.get("explore", {}).get("force_threshold", 0.0))
            force = None if state.contact_force is None else max(state.contact_force, least)
            arm = self.controller("explore", direction=state.direction, force_threshold=force,
                                  max_distance=state.max_distance, writes=written(state, ValueKind.POINT),
                                  hand_point=tuple(round(v, 6) for v in touching) if any(touching) else None)
            return NodeMapping("explore", arm, *self.hand_for_motion(state))
        posture, notes = self.perceiving_posture(state)
        radius, reach = self.robot.hand_radius(posture), self.robot.hand_reach(posture)
        container = {c.name: c for c in context.environment.containers}[state.container]  # validated
        method = state.method.value
        inside = min(container.inner_size[:2])
        if state.method is PerceptionMethod.BLIND_EXPLORATION and radius >= inside / 2:
            raise Unmappable(f"the {self.arm.hand.name} reaches {radius * 100:.1f} cm sideways in its '{posture}' "
                             f"posture: sweeping the '{container.name}' container ({inside * 100:.1f} cm across "
                             f"inside) it could not tell a wall from an object",
                             "use another method, a wider container, or a hand shape that keeps the hand narrower")
        if state.method is PerceptionMethod.VISION and not self.robot.cameras:
            raise Unmappable(f"the {self.name} has no depth camera to look with", "use a blind method")
        pinch = self.grasp_footprint(context)
        arm = self.controller("perceive", method=method, writes=written(state, ValueKind.POSE),
                              container_pose=container.pose.matrix, container_size=container.size,
                              container_wall=container.wall, hand_reach=round(reach, 6), hand_radius=round(radius, 6),
                              grasp_reach=round(max(self.robot.hand_reach(p) for p in self.robot.hand.postures), 6),
                              grasp_extent=tuple(round(e, 6) for e in self.robot.hand_extent(HandShape.OPEN.value)),
                              **self.jaw_band(context, pinch), **pinch,
                              sweep_extent=tuple(round(e, 6) for e in self.robot.hand_extent(posture, SWEEPING_TIP)),
                              hand_extent=tuple(round(e, 6) for e in self.robot.hand_extent(posture)),
                              tip_length=round(self.robot.tip_length(posture, SWEEPING_TIP), 6),
                              spread_tip=posture == HandShape.EXTEND.value)
        return NodeMapping("perceive", arm, self.controller("hand_shape", shape=posture), notes)

    def perceiving_posture(self, state: State) -> tuple[str, tuple[str, ...]]:
        """The posture a perceive state's hand takes: the state's shape, closed by default (the
        narrowest sweep), with a note where the hand makes only the closest shape; blind
        exploration's, with its fingers stretched where that is narrower still (the SDH2's fist
        sticks its thumb 11.5 cm out, its stretched fingers reach 5 cm)."""
        made, notes = self.shape(state.hand_shape or HandShape.CLOSED)
        posture = self.posture(made, state)
        if (state.hand_shape is None and state.method is PerceptionMethod.BLIND_EXPLORATION
                and HandShape.EXTEND.value in self.robot.hand.postures):
            posture = min((posture, HandShape.EXTEND.value), key=self.robot.hand_radius)
        return posture, notes

    def grasp_footprint(self, context: MappingContext) -> dict[str, tuple[float, ...] | float]:
        """What vision's approach is for, on a multi-finger hand: its pinch (a box round's grasp),
        its preshape's footprint (`hand_footprint`) about where it closes, given (`grasp_footprint`)
        along the axes of a hand turned `grasp_turn` (degrees) back from it, whose y the pinch
        closes along, as vision turns jaws: the Barrett's pinch closes along its x, 90 degrees.
        Zeros for a parallel jaw, alike either way round, and for a pinch that closes within
        ALONG_Y of no quarter turn of the hand's y."""
        none = {"grasp_footprint": (0.0, 0.0, 0.0, 0.0), "grasp_turn": 0.0}
        preshape = self.boxed(HandShape.PINCH_GRASP_PRESHAPE.value, context)
        pinch = self.boxed(HandShape.PINCH_GRASP.value, context)
        if self.arm.hand.kind == "parallel jaw" or preshape not in self.robot.hand.postures:
            return none
        line = self.robot.closing_line(preshape, pinch) if pinch in self.robot.hand.postures else None
        if line is None:
            return none
        quarters = round((np.pi / 2 - line) / (np.pi / 2))
        if abs(np.pi / 2 - line - quarters * np.pi / 2) > ALONG_Y:
            return none
        centre = self.robot.hand.grasp_centres.get(preshape, (0.0, 0.0, 0.0))
        extent, offset = self.footprint(preshape, (float(centre[0]), float(centre[1])))
        for _ in range(quarters % 4):  # the hand's x y seen from axes a quarter turn back: (x, y) -> (-y, x)
            extent, offset = (extent[1], extent[0]), (0.0 - offset[1], offset[0])
        return {"grasp_footprint": tuple(round(float(v), 6) for v in (*extent, *offset)),
                "grasp_turn": float((quarters % 4 * 90 + 180) % 360 - 180)}

    def footprint(self, posture: str, about: tuple[float, float] = (0.0, 0.0)
                  ) -> tuple[tuple[float, float], tuple[float, float]]:
        """The hand's footprint in a posture (`hand_footprint`), BOXED_CLEARANCE wider where
        the posture stands in to fit a box (`Hand.boxed`)."""
        extent, offset = self.robot.hand_footprint(posture, about)
        if posture in self.robot.hand.boxed.values():
            extent = (extent[0] + BOXED_CLEARANCE, extent[1] + BOXED_CLEARANCE)
        return extent, offset

    def boxed(self, posture: str, context: MappingContext | None) -> str:
        """The posture the hand makes for `posture`: in a task that knows a container, its
        narrower stand-in where it has one (`Hand.boxed`), else `posture` itself."""
        environment = context.environment if context is not None else None
        if environment is None or not environment.containers:
            return posture
        return self.robot.hand.boxed.get(posture, posture)

    def jaw_band(self, context: MappingContext, pinch: dict[str, tuple[float, ...] | float]
                 ) -> dict[str, tuple[float, ...]]:
        """The fingertips a box round's grasp comes down with, closing along the hand's y
        (`perceive`'s `jaw_band`): from the pads' half opening along it to how far the tips reach
        along it, and how far along the hand's x from where they close; and the hand's other
        lowest links there (`other_tips`: from and to along its x, either way along its y). A
        parallel jaw's open fingers; a multi-finger hand's pinch preshape where its pinch closes
        along the y: the SDH2's two fingers and its thumb, which come down on neighbours' tops
        (docs/empty-the-box.md, "The SDH2's fingertips and thumb kept off what the picture shows").
        Zeros for a pinch closing along another line (the Barrett's, along its x); `pinch` is
        the hand's `grasp_footprint` in `context`."""
        none = {"jaw_band": (0.0, 0.0, 0.0), "other_tips": (0.0, 0.0, 0.0)}
        if self.arm.hand.kind == "parallel jaw":
            inner = self.robot.pad_opening(HandShape.OPEN.value, np.pi / 2) / 2.0
            across, along = self.robot.hand_extent(HandShape.OPEN.value, SWEEPING_TIP)
            return {**none, "jaw_band": (round(inner, 6), round(along, 6), round(across, 6))}
        if pinch["grasp_turn"] != 0.0 or not any(pinch["grasp_footprint"]):
            return none
        preshape = self.boxed(HandShape.PINCH_GRASP_PRESHAPE.value, context)
        centre = self.robot.hand.grasp_centres.get(preshape, (0.0, 0.0, 0.0))
        (along, across), others = self.robot.low_tips(preshape, SWEEPING_TIP, (float(centre[0]), float(centre[1])))
        inner = self.robot.pad_opening(preshape, np.pi / 2) / 2.0
        return {"jaw_band": (round(inner, 6), round(along, 6), round(across, 6)),
                "other_tips": tuple(round(v, 6) for v in others)}

    @abstractmethod
    def map_node(self, state: State, context: MappingContext) -> NodeMapping:
        """The concrete primitive (arm and hand controllers) for one abstract primitive."""

    def map_event(self, event_type: EventType, seconds: float | None, transition: Transition,
                  context: MappingContext) -> ConditionNode:
        """The condition tree that detects one abstract event on the edge leaving `transition.origin`."""
        event_type = EventType(event_type)
        origin = context.state(transition.origin)
        if event_type is EventType.TIMEOUT:
            return self.condition(event_type, "timeout", seconds=seconds)
        if event_type is EventType.HARDWARE_FAILURE:  # D5 Fig. 2.3: arm OR hand failure
            return any_of(self.condition(event_type, "arm_fault"), self.condition(event_type, "hand_fault"),
                          self.condition(event_type, "simulation_unstable"))
        if event_type is EventType.ERROR:
            return any_of(self.condition(event_type, "arm_error"), self.condition(event_type, "hand_error"))
        if (event_type is EventType.SUCCESS and origin.type is StateType.TRANSPORT
                and EventType.GRASP_STABLE not in self.undetectable_events):
            # A transport that arrived without its object has not transported it; one whose
            # object drops out as soon as the arm stops has not either.
            return all_of(lasting(self.success(origin), HELD_FOR),
                          self.map_event(EventType.GRASP_STABLE, None, transition, context))
        if event_type is EventType.SUCCESS:
            return self.success(origin)
        if event_type in (EventType.OBJECT_FOUND, EventType.NOTHING_FOUND):
            return self.condition(event_type, event_type.value, value=written(origin, ValueKind.POSE))
        if event_type is EventType.OBJECT_IN_HAND:  # a look that gave up with its fingers on a grip
            return all_of(any_of(self.condition(event_type, "arm_error"), self.condition(event_type, "hand_error")),
                          self.condition(event_type, "fingers_pressing", posture=self.perceiving_posture(origin)[0],
                                         for_time=PRESSING_FOR))
        if event_type in (EventType.CONTACT, EventType.NO_CONTACT):  # explore's own verdict
            return self.condition(event_type, "arm_done" if event_type is EventType.CONTACT else "arm_error")
        if event_type in self.undetectable_events:
            raise Unmappable(f"the {self.name} has no sensor to detect '{event_type.value}'")
        sensed = self.sensed_event(event_type, origin)
        return self.carried(sensed, origin, context) if event_type is EventType.GRASP_STABLE else sensed

    def carried(self, held: ConditionNode, origin: State, context: MappingContext) -> ConditionNode:
        """grasp_stable means the object is held, not that the fingers touch something: once
        a transport has taken it off its support, the fingers must have stopped closing (a
        grip that keeps closing is squeezing the object out) and a wrist force-torque sensor
        must feel at least half its weight (the task's, or `load_held`'s default) beyond the
        empty hand; where the pads have taxel arrays, a grip whose contacts moved across them
        while the arm held still is watched longer (`slip_watched`: a mug turning in a Panda's
        jaws passed every other test and fell in the judge's hold). The hand's own reading
        must last as long as the stillness: a PyBullet SDH2 finger chattering on a turning
        object touched it every other tick, and one such tick passed a pad count that needed
        no time."""
        if origin.type is not StateType.TRANSPORT:
            return held
        refuse_uncarriable(context.object, f"transport state '{origin.name}'")
        still = self.condition(EventType.GRASP_STABLE, "fingers_still")
        held = pressing(lasting(held, float(still.params["for_time"])), carrying_force(context.object))
        parts = [held, still]
        tactile = self.arm.sensors_of(SensorKind.TACTILE)
        arrays = tuple(p.name for p in self.robot.hand.pads if p.taxels is not None and p.name in tactile)
        if arrays:
            parts.append(self.condition(EventType.GRASP_STABLE, "slip_watched", arrays))
        wrist = self.arm.sensors_of(SensorKind.FORCE_TORQUE)
        if wrist:
            weight = context.object.weight if context.object is not None else None
            # Half the weight, but no less than the least a load_held accepts (an object under 2 g).
            parts.append(self.condition(EventType.GRASP_STABLE, "load_held", wrist,
                                        weight=None if weight is None else round(max(weight / 2, WEIGHT.low), 6)))
        return all_of(*parts)

    def success(self, origin: State) -> ConditionNode:
        """Thesis 7.2.2: one abstract success may need the arm AND the hand controller done."""
        return all_of(self.condition(EventType.SUCCESS, "arm_done"), self.condition(EventType.SUCCESS, "hand_done"))

    def sensed_event(self, event_type: EventType, origin: State) -> ConditionNode:
        """grasp_stable, grasp_lost, finger_contact(_lost), collision: from this robot's sensors.

        A factory maps its hand's events and passes the rest here: a collision is an
        unexpected force on the wrist force-torque sensor, as on every arm that has one."""
        wrist = self.arm.sensors_of(SensorKind.FORCE_TORQUE)
        if event_type is EventType.COLLISION and wrist:
            return self.condition(event_type, "wrist_force_above", wrist)
        raise Unmappable(f"no mapping for event '{event_type.value}'")

    def place(self, state: State, context: MappingContext, target: Vec3 | None) -> Controller:
        """Thesis Eq. 3.4's `place` to `target`: the hand kept as it holds the object where a
        side grasp holds it (`held_from_side`), else turned top-down; the target is for the
        TCP with the object where the state's hand shape holds it (`acting_point`)."""
        point = self.acting_point(state)
        return self.controller("place", target=target, level=False if self.held_from_side(state, context) else None,
                               hand_point=tuple(round(v, 6) for v in point) if any(point) else None)

    def release(self, state: State, arm: str = "release_retreat") -> NodeMapping:
        """Thesis Eq. 3.5: open the hand to the state's opening while the arm backs off the
        surface (`release_retreat`), or holds still where the robot has no retreat."""
        return NodeMapping("release", self.controller(arm), self.controller("open_to", hand_position=state.hand_opening))

    # -- building blocks ------------------------------------------------------------------
    def controller(self, name: str, described: dict[str, ParamValue] | None = None, **params: ParamValue) -> Controller:
        """A controller with thesis defaults, then what the robot's description says of it
        (`described`), then this robot's config, then `params`."""
        merged = defaults(CONTROLLERS[name].params)
        merged.update(described or {})
        merged.update(self.config.controllers.get(name, {}))
        merged.update({k: v for k, v in params.items() if v is not None})
        return Controller(name=name, params=merged)

    def condition(self, event: EventType, kind: str, sensors: tuple[str, ...] = (), **params: ParamValue) -> Condition:
        """A leaf with defaults, then this robot's config for (event, kind), then `params`."""
        merged = defaults(CONDITIONS[kind].params)
        merged.update(self.config.conditions.get((event.value, kind), {}))
        merged.update({k: v for k, v in params.items() if v is not None})
        return Condition(kind=kind, sensors=sensors, params=merged)

    def shape(self, wanted: HandShape) -> tuple[HandShape, tuple[str, ...]]:
        """The shape to make for `wanted`, and a note when it is only the closest one."""
        hand = self.arm.hand
        if wanted in hand.shapes:
            return wanted, ()
        made = hand.closest[wanted]
        return made, (f"the {hand.name} cannot make '{wanted.value}'; using the closest shape '{made.value}'",)

    @cached_property
    def robot(self) -> RobotDescription:
        """The physical robot (its one source of truth, which the simulator also builds):
        `description()` in the `description.py` beside the factory's module, or beside the
        module of the factory it extends; for this arm."""
        arm = self.arm.name if len(self.arms) > 1 else None
        return description_module(type(self)).description(arm)

    @cached_property
    def info(self) -> RobotInfo:
        """What the robot's controllers know of it (limits, hand, pads, the hand's mass and
        centre of mass behind the wrist sensor): from this description, the belief, whatever
        the simulator that runs them is built from."""
        return robot_info(self.robot)

    def check_object_reach(self, context: MappingContext, state: State, *postures: str) -> None:
        """A grasp happens where the object is: refuse it when the arm cannot get there with
        the hand turned as it arrives (`turn_at_start`), or when the hand, in any of the
        `postures` it takes there, would cut into an obstacle of the task's environment, or,
        turned to grasp from the side, into the table. Such a hand closes on the obstacle, not
        on the object: the Barrett's pinch, whose knuckles stand 75 mm either side of its TCP,
        wrapped the walls of a box 150 mm wide inside, its pads pressing their outer faces,
        reported the object held, and lifted against the walls (empty_the_box.xml). A hand
        turned 90 degrees at a 4 cm tall grasp met the table on its way there on every robot
        (issue 32). A grasp from the side closes where its approach line passes the object's
        centre: the TCP of the hand as the state before it left it, moved along the approach."""
        self.check_payload(context)
        if context.object is None or context.object.pose is None:
            return
        centre = np.asarray(context.object.pose.position, float)
        rotation, line, from_above = self._grasp_line(context, state, centre)
        tcps = {}
        for posture in postures:
            grasp_centre = line + float((centre - line) @ rotation[:, 2]) * rotation[:, 2]
            tcps[posture] = grasp_centre - rotation @ np.asarray(self.robot.hand.grasp_centres.get(posture, (0.0,) * 3))
        if rotation is self._hand_down:
            self.check_reach(context.object.pose.position)
        else:
            self.check_pose(tuple(tcps[postures[0]]), rotation, f"grasping the object at "
                            f"({', '.join(f'{v:g}' for v in centre)}) from "
                            f"{'above, turned to it' if from_above else 'the side'}")
        for posture in postures:
            self.check_hand_room(context, posture, rotation, tcps[posture], f"closing on the object at "
                                 f"({', '.join(f'{v:g}' for v in centre)})")

    def _grasp_line(self, context: MappingContext, state: State,
                    centre: np.ndarray) -> tuple[np.ndarray, np.ndarray, bool]:
        """The hand's rotation as a grasp begins, a point of the line its approach follows, and
        whether it comes from above: top-down through the object's centre, turned to the
        object (`coming_down`), unless the state before turned the hand further than a grasp
        from above levels (the robust grasp's `level_within`); then along the turned hand's
        axis through where that state put the grasp centre."""
        turn = self.rolled(turn_at_start(context.task, state))
        if turn is None or self._from_above(turn):
            return self.coming_down(state, context), centre, True
        before = arriving(context.task, state)
        line = np.asarray(before.path[-1].position, float) if before is not None and before.path else centre
        return turn @ self._hand_down, line, False

    def rolled(self, turn: np.ndarray | None) -> np.ndarray | None:
        """The task's `turn` of the hand with the hand's own roll about its approach axis
        (`Hand.side_roll`) where the turn grasps from the side: the task says where the hand
        approaches from, the hand how it presents its fingers there."""
        roll = self.robot.hand.side_roll
        if turn is None or not roll or self._from_above(turn):
            return turn
        rolled = turn @ self._hand_down @ rotation_rpy((0.0, 0.0, roll)) @ self._hand_down.T
        try:
            tilt_of(rolled)
        except Unmappable as refused:
            raise Unmappable(f"the {self.arm.hand.name} rolls {np.degrees(roll):g} degrees about its approach to grasp "
                             f"from the side, its fingers across the object; with that roll {refused.reason}",
                             "approach from another side") from None
        return rolled

    def _from_above(self, turn: np.ndarray) -> bool:
        """A hand turned this way grasps from above: the grasp turns it down first."""
        within = np.radians(float(self.controller("robust_grasp_approach").params["level_within"]))
        return float((turn @ self._hand_down[:, 2]) @ self._hand_down[:, 2]) >= np.cos(within)

    def held_from_side(self, state: State, context: MappingContext) -> bool:
        """The hand comes into `state` still turned to the side by the task's last `<pose>`
        (`turn_at_start`: a side grasp it holds): a place puts the object down as it is held."""
        held = self.rolled(turn_at_start(context.task, state))
        return held is not None and not self._from_above(held)

    def check_hand_room(self, context: MappingContext, posture: str, rotation: np.ndarray, tcp_at: np.ndarray,
                        doing: str) -> None:
        """The hand in `posture` with its TCP at `tcp_at`, turned by `rotation`, keeps
        HAND_CLEARANCE from every obstacle and, when not pointing down, from the table."""
        tcp = np.eye(4)
        tcp[:3, :3], tcp[:3, 3] = rotation, tcp_at
        obstacles = [o for o in (context.environment.obstacles if context.environment else ()) if o.size]
        room = [(o.position, tuple(v + 2 * HAND_CLEARANCE for v in o.size)) for o in obstacles]
        hit = self.robot.hand_in_boxes(posture, tcp, room) if room else {}
        if hit:
            where = " and ".join(f"({', '.join(f'{v:g}' for v in obstacles[k].position)}) sized "
                                 f"{' x '.join(f'{v:g}' for v in obstacles[k].size)}" for k in hit)
            links = [name for name in self.robot.hand_links if any(name in names for names in hit.values())]
            them = "them" if len(hit) > 1 else "it"
            raise Unmappable(
                f"the {self.arm.hand.name} in its '{posture}' posture, {doing}, would come within "
                f"{HAND_CLEARANCE * 100:g} cm of the {'obstacles' if len(hit) > 1 else 'obstacle'} at {where} with its "
                f"{_listed(links)}: it would close on {them} or land on {them}, not on the object",
                "give the hand more room around the object (move the obstacle away), "
                "or choose a robot or arm with a smaller hand")
        if float(rotation[2, 2]) <= -1.0 + 1e-9:
            return  # a hand pointing down meets the table with its fingertips, as its grasp expects
        lowest, links = self.robot.hand_below(posture, tcp, HAND_CLEARANCE)
        if links:
            needed = float(tcp_at[2]) - lowest + HAND_CLEARANCE
            raise Unmappable(
                f"the {self.arm.hand.name} turned as the task turns it, in its '{posture}' posture, {doing}, "
                f"would reach {max(0.0, -lowest) * 100:.1f} cm into the table, within {HAND_CLEARANCE * 100:g} cm "
                f"of it, with its {_listed(links)}",
                f"put the TCP at least {needed:.3f} m above the table with this turn (it is at {tcp_at[2]:.3f} m), "
                f"or grasp from above")

    def hand_for_motion(self, state: State, context: MappingContext | None = None
                        ) -> tuple[Controller, tuple[str, ...]]:
        """The hand during an arm motion: the state's hand shape (or the closest this hand
        makes, with a note; `boxed` in a task that knows a container), or kept as it is when
        the state names none."""
        if state.hand_shape is None:
            return self.controller("hold_position"), ()
        shape, notes = self.shape(state.hand_shape)
        return self.controller("hand_shape", shape=self.boxed(self.posture(shape, state), context)), notes

    def posture(self, shape: HandShape, state: State) -> str:
        """The hand's posture for a shape in a state: a closed hand holds nothing, so in a
        move, push or explore it takes the posture its description pushes with (`Hand.push_posture`)."""
        if shape is HandShape.CLOSED and state.type in (StateType.MOVE, StateType.PUSH, StateType.EXPLORE):
            return self.robot.hand.push_posture
        return shape.value

    def jaw_grasp(self, state: State, context: MappingContext) -> NodeMapping:
        """A parallel gripper's grasp (thesis 7.3, Melfa): the jaws close until the grip force
        is reached, while the arm corrects the approach on contact (thesis 3.3.1)."""
        notes = self.shape(state.hand_shape)[1] if state.hand_shape else ()
        self.check_object_reach(context, state, *self.grasp_postures(state))
        arm = self.controller("jaw_grasp_correction", wrist_to_tcp=round(self._wrist_to_tcp, 6),
                              fingertip_reach=round(self.robot.hand_reach(HandShape.OPEN.value), 6),
                              fingertip_extent=tuple(round(e, 6) for e in
                                                     self.robot.hand_extent(HandShape.OPEN.value, SWEEPING_TIP)),
                              hand_extent=tuple(round(e, 6) for e in self.robot.hand_extent(HandShape.OPEN.value)),
                              locate_along=self.places_unweighed(context) or None, wrist_roll=self.wrist_roll())
        return NodeMapping("grasp", arm, self.controller("close_until_force"), notes)

    def places_unweighed(self, context: MappingContext) -> bool:
        """Whether the task places the object it knows (the grasp's to look for) with a place
        that cannot weigh where the hand holds it (`weigh_time` 0): the grasp must then see
        where it closes on the object."""
        known = context.object is not None and context.object.pose is not None
        places = any(s.type is StateType.PLACE for s in context.task.states)
        return known and places and float(self.controller("place").params["weigh_time"]) <= 0.0

    def jaw_unscrew(self, state: State) -> NodeMapping:
        """Thesis 3.3.6's unscrew on a parallel gripper, as a real one unscrews: the jaws grip
        the cap as this gripper's grasp grips anything (its closing speed, its grip-force
        sensing, its re-centring), the last wrist joint twists it, the arm pulls; the arm
        side is the one the fingertip pinch uses. The grasp centre is the TCP, between the pads;
        the cap's width lets the arm find the jaws' room around it (`UnscrewArm`'s seat)."""
        grip = self.controller("close_until_force").params
        hand = self.controller("unscrew_jaws", closing_speed=grip["closing_speed"],
                               force_source=grip["force_source"], max_recentre=grip["max_recentre"])
        arm = self.controller("unscrew_arm", wrist_turn=self.wrist_turn(state), cap_width=state.object_size or 0.0)
        return NodeMapping("unscrew", arm, hand, self.shape(state.hand_shape)[1] if state.hand_shape else ())

    def wrist_turn(self, state: State) -> float:
        """The unscrew's twist turns the hand about its approach axis: +1 or -1, the way the
        last arm joint turns with it (at home, in the robot's own geometry). Refused where
        that joint does not roll the hand (a twist would swing the cap round an axis of its
        own) or cannot turn one twist's TWIST_ANGLE in all its range."""
        name = self.robot.arm_joints[-1]
        joint = self.robot.joints[name]
        along = -self.wrist_roll()  # about the approach axis, which points down
        if not along:
            raise Unmappable(f"unscrew state '{state.name}': the last joint of the {self.arm.description}, '{name}', "
                             "does not roll the hand about its approach axis, so no twist turns the cap on its axis",
                             "translate the task for a robot whose wrist rolls the hand")
        try:
            angle = float(state.parameters.get("twist_angle", self.controller("unscrew_arm").params["twist_angle"]))
        except ValueError:  # the translator reports the bad value, located
            return along
        span = float(np.degrees(joint.upper - joint.lower))
        if span < angle:
            raise Unmappable(f"unscrew state '{state.name}': the wrist joint '{name}' of the {self.arm.description} "
                             f"turns {span:.0f} degrees in all, less than one twist of {angle:g} degrees (TWIST_ANGLE)",
                             "set a smaller <parameter name=\"twist_angle\">, or translate for a robot whose wrist "
                             "turns further")
        return along

    @cached_property
    def _wrist_along(self) -> float:
        """How the last arm joint's axis lies along the hand's approach axis at home (the
        cosine): +-1 for a wrist that rolls the hand, as every arm's does."""
        robot, home = self.robot, np.asarray(self.robot.home, float)
        return float(robot.tcp_jacobian(home)[3:, -1] @ robot.tcp_pose(home)[:3, 2])

    def wrist_roll(self) -> float:
        """How the last arm joint turns per turn of a hand pointing down about the world
        vertical (its approach axis the other way): -1 or +1; 0 where that joint does not
        roll the hand. A move to a perceived yaw chooses its way with it (`cartesian_move`)."""
        joint = self.robot.joints[self.robot.arm_joints[-1]]
        along = self._wrist_along
        return 0.0 if joint.kind != "revolute" or abs(along) < WRIST_ALIGNED else -float(np.sign(along))

    @cached_property
    def _wrist_to_tcp(self) -> float:
        """Distance from the wrist sensor to the TCP along the hand's approach axis."""
        robot = self.robot
        joints = dict(zip(robot.arm_joints, (float(v) for v in robot.home)))
        tcp = robot.site_pose(robot.tcp, joints)
        return float((tcp[:3, 3] - robot.site_pose(robot.wrist_sensor, joints)[:3, 3]) @ tcp[:3, 2])

    def check_payload(self, context: MappingContext) -> None:
        """An object heavier than the arm's published payload is not this robot's to lift."""
        weight = context.object.weight if context.object else None
        if weight is not None and self.robot.payload is not None and weight > self.robot.payload:
            raise Unmappable(f"the object weighs {weight:g} kg, over the {self.robot.payload:g} kg payload of the "
                             f"{self.arm.description}",
                             "choose a robot or arm with a larger payload, or check the object's <weight>")

    def check_reach(self, *points: Vec3) -> None:
        """Each point must be reachable by the TCP with the hand pointing down."""
        for point in points:
            if not self._reach.reachable(point):
                raise Unmappable(
                    f"target ({point[0]:g}, {point[1]:g}, {point[2]:g}) is out of reach of the "
                    f"{self.arm.description} with the hand pointing down",
                    "move the target into the work area, or choose a robot or arm that reaches it")

    def check_pose(self, point: Vec3, rotation: np.ndarray, doing: str) -> None:
        """The TCP must get to `point` with the hand turned by `rotation` (world), as the arm,
        moving from home as the run moves it, gets there (`Reach.why_not`)."""
        why = self._reach.why_not(point, rotation)
        if why is not None:
            raise Unmappable(
                f"target ({point[0]:g}, {point[1]:g}, {point[2]:g}), {doing}, is out of reach of the "
                f"{self.arm.description} with the hand turned as the task turns it: {why}",
                "turn the hand less or approach from another side or height, move the target into the work "
                "area, or choose a robot or arm that reaches it")

    @cached_property
    def _reach(self) -> Reach:
        return Reach(self.robot)

    def motion(self, state: State, context: MappingContext) -> tuple[Vec3 | None, tuple[Vec3, ...]]:
        """Target and via points of an arm primitive: the path, or derived from the object,
        for the point the state's hand shape acts at (`shape_offset`), turned into TCP points.
        None for a target read from a named value: the run sets it as the state starts
        (`atd.runtime.values`), a TCP position as the perceptual primitive wrote it."""
        if state.target_from is not None:
            return None, ()
        turn = self.rolled(target_turn(state))
        held = turn if turn is not None or state.type not in KEEPING else \
            self.rolled(turn_at_start(context.task, state))
        down = self.coming_down(state, context)
        offset = np.asarray(self.shape_offset(state, down), float)
        # the shape's point turns with the hand: a pose's turn, or the side turn a grasp holds the object with
        turned = held is not None and (turn is not None or not self._from_above(held))
        dx, dy, dz = held @ offset if turned else offset
        points = [w.position for w in state.path] if state.path else [derived_target(state, context.object)]
        # To the micrometre, so the ESTD's 9-digit numbers read back equal.
        points = [(round(x - dx, 6), round(y - dy, 6), round(z - dz, 6)) for x, y, z in points]
        if down is not self._hand_down:
            for point in points:
                self.check_pose(point, down, f"of {state.type.value} state '{state.name}', turned to the object")
            return points[-1], tuple(points[:-1])
        if held is None or (turn is None and self._from_above(held)):
            self.check_reach(*points)
            return points[-1], tuple(points[:-1])
        if turn is not None:
            tilt_of(turn)  # a turn no arm controller makes is refused as such, before its reach
        rotation = held @ self._hand_down
        for point in points:
            self.check_pose(point, rotation, f"of {state.type.value} state '{state.name}'")
        if turn is not None and state.hand_shape is not None and not self._from_above(turn):
            posture = self.posture(self.shape(state.hand_shape)[0], state)
            self.check_hand_room(context, posture, rotation, np.asarray(points[-1], float),
                                 f"at the target of {state.type.value} state '{state.name}'")
        return points[-1], tuple(points[:-1])

    def arm_motion(self, state: State, context: MappingContext, target: Vec3, via: tuple[Vec3, ...],
                   **extra: ParamValue) -> Controller:
        """The arm controller of a move-like state: `push` for an ATD push (a guarded move
        that must feel the object), `cartesian_move` with the ATD's movement type otherwise.
        A move carrying the object has arrived only where it was going: a transport that
        meets resistance on the way, or a place that meets it above its surface, stopped
        short (`contact_margin`). A path ending on a `<pose>` turns the hand as the pose
        says (`tilt`); otherwise a transport keeps the hand's orientation (`level` off), and
        a move the hand comes down on the object by turns it to the object (`coming_down`: `yaw`)."""
        flags = arm_motion_flags(state)
        if state.type is StateType.PUSH:
            return self.controller("push", target=target, waypoints=via, keep_orientation=flags["keep_orientation"])
        if state.target_from is not None:  # read at run time: the move places the shape's point on it
            touched = value_kinds(context.task).get(state.target_from, (None,))[0] is ValueKind.POINT
            pinch = leads_into(context.task, state, StateType.UNSCREW) if touched else None
            if any(point := self.acting_point(state, touched, pinch)):
                extra = {**extra, "hand_point": tuple(round(v, 6) for v in point)}
            if not touched and (roll := self.wrist_roll()):  # a pose's yaw, turned to the way the wrist has room
                extra = {**extra, "wrist_roll": roll}
        margin = CARRIED_MARGIN.get(state.type)
        carried: dict[str, ParamValue] = {} if margin is None else {"contact_margin": margin}
        turn = self.rolled(target_turn(state))
        down = self.coming_down(state, context)
        if turn is not None:
            carried["tilt"] = tilt_of(turn)
        elif state.type is StateType.TRANSPORT or (state.type is StateType.PLACE and self.held_from_side(state, context)):
            carried["level"] = False  # the object as the grasp holds it: see cartesian_move's `level`
        elif down is not self._hand_down:
            carried["yaw"] = round(float(np.degrees(np.arctan2(down[1, 0], down[0, 0]))), 6)
            if float(down[:, 0] @ self._hand_down[:, 0]) < 0.0:  # half a turn further: the wrist's way, not the shorter
                carried["either_way"] = False
        return self.controller("cartesian_move", target=target, waypoints=via, **{**flags, **carried, **extra})

    def shape_offset(self, state: State, down: np.ndarray) -> Vec3:
        """Where the state's hand shape acts, from the TCP, in the world frame, the hand
        pointing down turned as `down` (its yaw at home, or turned to the object it comes
        down on: `coming_down`), which every arm controller keeps.

        The task's positions are for that point. A pinch closes where the hand says
        (`Hand.grasp_centres`: the SDH2's two fingers face each other 19 mm off its TCP).
        A closed hand holds nothing: in a move or push it takes its push posture. A gripper
        pushes with its closed jaws: no change. A three-finger hand points one finger down,
        and that finger's lowest point (`grasp_centres` off the TCP, `hand_reach` below it)
        stands in for the TCP, so a push meets the object where the path says.
        """
        x, y, z = (float(v) for v in down @ np.asarray(self.acting_point(state), float))
        return (x, y, z)

    def acting_point(self, state: State, touching: bool = False, pinch: State | None = None) -> Vec3:
        """Where the state's hand shape acts, from the TCP in the hand frame (`shape_offset`
        says which point that is); the TCP itself when the state names no shape. `touching`:
        the state touches, or goes to a point an explore touched (a `point` value), so its
        hand acts with its lowest point, pads counted (`touch_reach`), under that: the task says where the
        fingertips go from a felt surface, and each hand's own geometry (the SDH2's thumb
        21 mm under its TCP and 57 mm from its pinch, a gripper's jaws 10-24 mm under its
        TCP) puts its TCP there. A path for the hand's lowest point (`<path for="lowest_point">`)
        acts so too: the task says how high over a floor the hand's lowest point drags,
        whichever hand it is (a gripper acts at its grasp centre, 10-24 mm above its jaws'
        ends; a pointing finger at its tip). `pinch`: the unscrew the state ends where it pinches, so
        the point is the lower edge of the pads closed to its `object_size` (`pinch_reach`):
        the task says how far under a felt cap top the pads pinch, and each hand's pads get
        there (a Barrett's pad tips meet a 60 mm cap 5 mm over its preshape's lowest point,
        the SDH2's pads' edge is 3 mm over its fingertips', a gripper's jaws end with their pads),
        but for the hand's own `pinch_clearance` over it."""
        if state.hand_shape is None:
            return (0.0, 0.0, 0.0)
        touching = touching or state.path_for is PathPoint.LOWEST_POINT
        made, _ = self.shape(state.hand_shape)
        posture = self.posture(made, state)
        robot = self.robot
        x, y, z = (float(v) for v in robot.hand.grasp_centres.get(posture, (0.0, 0.0, 0.0)))
        if touching or posture != made.value:  # a push posture of its own: its lowest point
            z = robot.touch_reach(posture) if touching else robot.hand_reach(posture)
        if touching and pinch is not None and pinch.object_size is not None:
            closing = self.shape(pinch.hand_shape or HandShape.PINCH_GRASP)[0].value
            if (edge := robot.pinch_reach(posture, closing, pinch.object_size)) is not None:
                z = edge + robot.hand.pinch_clearance
        return (x, y, z)

    def coming_down(self, state: State, context: MappingContext) -> np.ndarray:
        """The hand pointing down as a move brings it onto the object a grasp then closes on,
        turned about the vertical so that its pads close across the object's narrowest width
        as the task believes it stands (`grasp_turn`), by the least turn the arm reaches with
        every joint TURN_MARGIN from its limits, else half a turn further (the pads close
        along the same line) where that keeps the margin, else the least turn it reaches at
        all (a quarter turn either way closes alike: TIE_SHORT). `_hand_down` itself (the home yaw)
        where no turn is needed (the open pads take the object with room) or reached, where
        the task turns the hand on the way there (`_turnable`), or where it does not say the
        object's shape or size. A grasp state is turned as the move it comes from."""
        if state.type is StateType.GRASP:  # as the move it comes from left the hand
            before = arriving(context.task, state)
            return self.coming_down(before, context) if before is not None and before.type is StateType.MOVE \
                else self._hand_down
        grasp = grasp_ahead(context.task, state) if state.type is StateType.MOVE and self._turnable(state) else None
        before = arriving(context.task, grasp) if grasp is not None else None
        if grasp is None or before is None or not self._turnable(before):
            return self._hand_down
        obj = context.acting_on(grasp.object).object
        if obj is None or obj.pose is None or not (obj.size or obj.object_class):
            return self._hand_down
        try:
            start, end = self.grasp_postures(grasp)
        except Unmappable:  # the grasp state says why
            return self._hand_down
        line = self.robot.closing_line(start, end)
        if line is None:
            return self._hand_down
        closing = self._hand_down @ (np.cos(line), np.sin(line), 0.0)  # the pads' line in the world, at home
        turn = grasp_turn(obj, float(np.arctan2(closing[1], closing[0])), self.robot.pad_opening(start, line))
        if abs(turn) < TURN_TOLERANCE:
            return self._hand_down
        ways = [turn, turn - np.copysign(np.pi, turn)]  # half a turn further the pads close along the same line
        if abs(turn) > np.pi / 2 - TIE_SHORT:  # a quarter turn either way: each TIE_SHORT short of it
            ways = [float(np.clip(w, TIE_SHORT - np.pi / 2, np.pi / 2 - TIE_SHORT)) for w in ways]
        centre = np.asarray(obj.pose.position, float)
        reached = []
        for way in ways:
            down = rotation_rpy((0.0, 0.0, way)) @ self._hand_down
            tcps = [tuple(centre - down @ np.asarray(self.robot.hand.grasp_centres.get(p, (0.0,) * 3)))
                    for p in (start, end)]
            if all(self._reach.why_not(tcp, down) is None for tcp in tcps):
                if min(self._reach.margin(tcp, down) for tcp in tcps) >= TURN_MARGIN:
                    return down
                reached.append(down)
        return reached[0] if reached else self._hand_down

    @staticmethod
    def _turnable(move: State) -> bool:
        """A move whose hand's turn the task leaves to the robot: its target neither a `<pose>`
        nor a named value (a perceived approach brings its own yaw)."""
        return move.target_from is None and target_turn(move) is None

    def grasp_postures(self, state: State) -> tuple[str, str]:
        """The postures a grasp state's hand closes from and to: a gripper's open jaws to its
        grasp (`jaw_grasp`)."""
        closed = self.shape(state.hand_shape)[0] if state.hand_shape else HandShape.CLOSED
        return HandShape.OPEN.value, closed.value

    @cached_property
    def _hand_down(self) -> np.ndarray:
        """The hand's rotation pointing down (hand z = world -z) with its home yaw."""
        robot = self.robot
        x = robot.tcp_pose(np.asarray(robot.home, float))[:3, 0].copy()
        x[2] = 0.0
        x /= np.linalg.norm(x)
        z = np.array([0.0, 0.0, -1.0])
        return np.column_stack([x, np.cross(z, x), z])


def written(state: State, kind: ValueKind) -> str:
    """The name a perceptual state writes its value of `kind` under: its `<writes>`, or the
    state's own name when it names none (the controller and its events must agree)."""
    return next((v.name for v in state.writes if v.kind is kind), state.name)


def derived_target(state: State, obj: ObjectInfo | None) -> Vec3:
    """Thesis 7.2: the end pose is usually enough; without a path, take it from the object.

    A free approach ends above the object, a guarded move descends to grasp height (the
    object's centre, where the TCP holds it), a transport lifts, a place puts the object
    back where it was. A push or slide needs to know where to: the object cannot say.
    """
    if state.type in (StateType.PUSH, StateType.SLIDE):
        raise Unmappable(f"it has no path, and the object information says where the object is, not where to "
                         f"{state.type.value} it",
                         "add <path><position>x y z</position></path> with the destination")
    if obj is None or obj.pose is None:
        raise Unmappable("it has no path, and the task gives no object pose to derive a target from",
                         "add <path><position>x y z</position></path>, or an <object> with a <pose>")
    x, y, z = obj.pose.position
    if state.type is StateType.TRANSPORT:
        return (x, y, z + LIFT_HEIGHT)
    if state.type is StateType.PLACE or state.movement is Movement.GUARDED:
        return (x, y, z)
    return (x, y, z + obj.half_height + APPROACH_CLEARANCE)


def all_of(*children: ConditionNode) -> ConditionGroup:
    """A condition that holds when every child holds (thesis 7.2.2: arm AND hand done)."""
    return ConditionGroup(op="all", children=children)


def any_of(*children: ConditionNode) -> ConditionGroup:
    """A condition that holds when any child holds (D5 Fig. 2.3: arm OR hand failure)."""
    return ConditionGroup(op="any", children=children)


def lasting(node: ConditionNode, seconds: float) -> ConditionNode:
    """`node` with every leaf required to hold for at least `seconds` (its `for_time`)."""
    if isinstance(node, ConditionGroup):
        return node.model_copy(update={"children": tuple(lasting(c, seconds) for c in node.children)})
    if "for_time" not in node.params or float(node.params["for_time"]) >= seconds:
        return node
    return node.model_copy(update={"params": {**node.params, "for_time": seconds}})


def pressing(node: ConditionNode, force: float) -> ConditionNode:
    """`node` with every pad-force leaf asking at least `force` of each pad."""
    if isinstance(node, ConditionGroup):
        return node.model_copy(update={"children": tuple(pressing(c, force) for c in node.children)})
    if node.kind != "tactile_force_above" or float(node.params["force_threshold"]) >= force:
        return node
    return node.model_copy(update={"params": {**node.params, "force_threshold": round(force, 3)}})


LEVEL_SLACK = 1e-6  # of the approach axis's rise: a turn of exactly 90 degrees, rounded, is level


def tilt_of(turn: np.ndarray) -> tuple[float, float, float]:
    """`turn` as cartesian_move's tilt: roll, pitch, yaw about the world axes, in degrees;
    a turn that points the hand's approach above the horizontal is refused: no hand grasps
    from below."""
    tilt = tuple(round(float(np.degrees(a)), 3) for a in rpy_of(turn))
    upward = float(turn[2] @ (0.0, 0.0, -1.0))  # the turned approach axis's world z
    if upward > LEVEL_SLACK:
        angle = float(np.degrees(np.arccos(np.clip(-upward, -1.0, 1.0))))
        raise Unmappable(f"its <pose> turns the hand by roll {tilt[0]:g}, pitch {tilt[1]:g}, yaw {tilt[2]:g} degrees "
                         f"from pointing down: {angle:.0f} degrees, its approach past the horizontal",
                         "give the pose's rotation as the hand's turn away from top-down (identity: straight down), "
                         "at most 90 degrees")
    return tilt  # type: ignore[return-value]


def arm_motion_flags(state: State) -> dict[str, bool]:
    """Thesis 7.2 motion types: guarded = straight Cartesian line; constrained = orientation held."""
    return {"straight_line": state.movement is Movement.GUARDED,
            "keep_orientation": state.movement is Movement.CONSTRAINED}



def obstacle_params(context: MappingContext) -> dict[str, tuple[tuple[float, ...], ...]]:
    """Table 7.3's transport extra parameter: the environment's obstacles, for the arm to avoid.

    An obstacle written without a size is a point (size 0 0 0), as in D5 Table 2.1.
    """
    obstacles = context.environment.obstacles if context.environment else ()
    if not obstacles:
        return {}
    return {"obstacles": tuple(o.position for o in obstacles),
            "obstacle_sizes": tuple(o.size or (0.0, 0.0, 0.0) for o in obstacles)}


GRIP_SAFETY = 2.0  # times the weight friction must carry: at once, a lifted weight slid out (docs/constants.md)


def carrying_force(obj: ObjectInfo | None) -> float:
    """The force each of two opposed pads must press with for friction to carry the
    object's weight at all; below it the object is sliding out (docs/constants.md). 0 when
    the task does not say the object's weight and friction."""
    return holding_force(obj) / GRIP_SAFETY


def refuse_uncarriable(obj: ObjectInfo | None, where: str) -> None:
    """Refuse a task whose object no pad force any grasp may ask could carry (its weight
    against its friction), naming the state `where` it would be grasped or carried."""
    needed = holding_force(obj)
    if obj is not None and needed > FORCE.high:
        raise Unmappable(f"{where}: friction {obj.friction:g} carries a {obj.weight:g} kg object only if each pad "
                         f"presses {needed:.0f} N, over the {FORCE.high:g} N any grasp force may be",
                         "check the object's <weight> and <friction>")


def holding_force(obj: ObjectInfo | None) -> float:
    """The force each of two opposed pads must press with for friction to carry the
    object's weight GRIP_SAFETY times over; 0 when the task does not say its weight and
    friction (then the robot's configured grasp force stands)."""
    if obj is None or obj.weight is None or not obj.friction:
        return 0.0
    return GRIP_SAFETY * obj.weight * GRAVITY / (2.0 * obj.friction)


def grasp_width(obj: ObjectInfo) -> float:
    """Width the fingers close across, top-down (the robot API's name for
    `ObjectInfo.footprint_width`): a box's narrower side, a round object's diameter."""
    return obj.footprint_width


def parallel_jaw_closest() -> dict[HandShape, HandShape]:
    """A parallel jaw opens, closes, and has one grasp (D5 2.2.2): every preshape becomes
    'open', every grasp 'pinch_grasp', and extended fingers the closed jaws."""
    grasps = {HandShape.POWER_GRASP, HandShape.CYLINDRICAL_GRASP, HandShape.SPHERICAL_GRASP, HandShape.HOOK_GRASP}
    closest = {s: HandShape.PINCH_GRASP if s in grasps else HandShape.OPEN for s in HandShape}
    closest.update({HandShape.EXTEND: HandShape.CLOSED, HandShape.EXTEND_FINGER: HandShape.CLOSED})
    return {s: made for s, made in closest.items() if s not in PARALLEL_JAW_SHAPES}


PARALLEL_JAW_SHAPES = frozenset({HandShape.OPEN, HandShape.CLOSED, HandShape.PINCH_GRASP})


def _listed(names: list[str]) -> str:
    """'a', 'a and b', 'a, b and c'."""
    return " and ".join([", ".join(names[:-1]), names[-1]] if len(names) > 1 else names)
