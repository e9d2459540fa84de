"""The Abstract Task Description as data: a directed multigraph of abstract primitives
joined by abstract events, plus what is known of the object and its surroundings.

The models say what a well-formed task *is*; `atd.model.reader` turns a file into them
and reports what is wrong with the file, `atd.model.validate` checks the graph.
"""

from __future__ import annotations

import math
from functools import cached_property
from typing import TYPE_CHECKING, Any, Literal, NamedTuple

from atd.model.frozen import Frozen
from pydantic import Field, InstanceOf

from atd.model.vocabulary import (
    DEFAULT_SIZE,
    EventType,
    HandShape,
    Movement,
    ObjectClass,
    PathPoint,
    PerceptionMethod,
    StateType,
    ValueKind,
)

if TYPE_CHECKING:
    import numpy as np

Vec3 = tuple[float, float, float]


class Location(NamedTuple):
    """Where an element was written, so every diagnostic can point at it. A named tuple, not a
    dataclass: a large task has one per element, and a tuple is half the cost to make."""

    file: str
    line: int
    col: int = 1

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.col}" if self.line else self.file


class AtdElement(Frozen):
    """Base of every ATD element: immutable, and equal when it means the same thing.

    The source location is carried along for diagnostics but is not part of the
    meaning, so a task read back from the file it was written to equals the original.
    """

    loc: InstanceOf[Location] | None = Field(default=None, exclude=True, repr=False)  # made by the reader, not a user

    def __eq__(self, other: object) -> bool:
        return type(self) is type(other) and self.model_dump() == other.model_dump()  # type: ignore[union-attr]

    def __hash__(self) -> int:
        return hash(repr(self.model_dump()))


class Pose(AtdElement):
    """A rigid transform written as 16 numbers: a row-major 4x4 homogeneous matrix."""

    matrix: tuple[float, ...] = Field(min_length=16, max_length=16)

    @classmethod
    def from_position(cls, xyz: Vec3) -> Pose:
        x, y, z = (float(v) for v in xyz)
        return cls(matrix=(1.0, 0.0, 0.0, x, 0.0, 1.0, 0.0, y, 0.0, 0.0, 1.0, z, 0.0, 0.0, 0.0, 1.0))

    def as_array(self) -> np.ndarray:
        import numpy as np  # here, not at the top: reading and checking tasks needs no numpy (start-up time)

        return np.asarray(self.matrix, dtype=float).reshape(4, 4)

    @property
    def position(self) -> Vec3:
        m = self.matrix
        return (m[3], m[7], m[11])


class ObjectInfo(AtdElement):
    """What the task knows of an object it manipulates (D5 Table 2.1). `name` tells apart
    the objects of a task that knows several; a task's one object may go unnamed."""

    name: str | None = None
    pose: Pose | None = None
    weight: float | None = None  # kg
    inertia: tuple[float, ...] | None = None  # 3x3, row-major, kg m^2
    shape: str | None = None  # mesh file, relative to the ATD
    friction: float | None = None
    object_class: ObjectClass | None = None
    size: tuple[float, ...] | None = None  # per class: see vocabulary.SIZE_LAYOUT

    @property
    def effective_size(self) -> tuple[float, ...]:
        """The size to simulate and plan with: the file's own, or the class default."""
        if self.size is not None:
            return self.size
        return DEFAULT_SIZE[self.object_class or ObjectClass.BOX]

    @property
    def half_height(self) -> float:
        """Distance from the object's centre to its resting face, along world z."""
        size = self.effective_size
        kind = self.object_class or ObjectClass.BOX
        if kind is ObjectClass.BOX:
            return size[2] / 2
        if kind is ObjectClass.CYLINDER:
            return size[1] / 2
        return size[0]

    @property
    def least_width(self) -> float:
        """The narrowest the object is, whichever way it is taken: fingers that close past
        it have nothing between them."""
        size = self.effective_size
        kind = self.object_class or ObjectClass.BOX
        if kind is ObjectClass.BOX:
            return min(size)
        if kind is ObjectClass.CYLINDER:
            return min(2 * size[0], size[1])
        return 2 * size[0]

    @property
    def footprint_width(self) -> float:
        """The shorter side of the object's footprint on its resting face (a box), or its
        diameter: the width fingers closing top-down close across."""
        size = self.effective_size
        if (self.object_class or ObjectClass.BOX) is ObjectClass.BOX:
            return min(size[0], size[1])
        return 2 * size[0]

    @property
    def footprint_length(self) -> float:
        """The longer side of the object's footprint on its resting face (a box), or its
        diameter: how far it reaches across a pinch planned across its narrow side."""
        size = self.effective_size
        if (self.object_class or ObjectClass.BOX) is ObjectClass.BOX:
            return max(size[0], size[1])
        return 2 * size[0]

    @property
    def widest(self) -> float:
        """The widest the object is across, whichever way it stands on its resting face:
        fingers that stop further apart than this are not stopped by it."""
        size = self.effective_size
        if (self.object_class or ObjectClass.BOX) is ObjectClass.BOX:
            return math.hypot(size[0], size[1])
        return 2 * size[0]


class Obstacle(AtdElement):
    """Something to keep clear of: a position, and as our extension a box size."""

    position: Vec3
    size: Vec3 | None = None


class ContainerInfo(AtdElement):
    """An open box the robot knows (thesis 3.4.3: its pose and size, not what is in it),
    given as a world file gives one (docs/worlds.md): `pose` is the centre of its floor's
    underside, `size` its outer lengths along its own axes, `wall` the thickness of its
    walls and floor."""

    name: str
    pose: Pose
    size: Vec3
    wall: float = 0.01

    @property
    def inner_size(self) -> Vec3:
        """The room inside: what perception searches and a hand reaches into."""
        sx, sy, sz = self.size
        return (sx - 2 * self.wall, sy - 2 * self.wall, sz - self.wall)


class Environment(AtdElement):
    obstacles: tuple[Obstacle, ...] = ()
    containers: tuple[ContainerInfo, ...] = ()


class Value(AtdElement):
    """A named value a state writes or a sub-task takes as input, and what it holds."""

    name: str
    kind: ValueKind


class Waypoint(AtdElement):
    """A point of a state's path. `position` and `point` give 3 numbers, `pose` 16."""

    kind: Literal["position", "pose", "point"]
    values: tuple[float, ...]

    @property
    def position(self) -> Vec3:
        v = self.values
        return (v[3], v[7], v[11]) if self.kind == "pose" else (v[0], v[1], v[2])


class State(AtdElement):
    """A node: an abstract primitive with its parameters, a sub-task or an end state."""

    name: str
    type: StateType
    movement: Movement | None = None
    hand_shape: HandShape | None = None
    path: tuple[Waypoint, ...] = ()
    path_for: PathPoint = PathPoint.HAND_SHAPE  # which point of the hand the path's positions are for
    preshape: HandShape | None = None  # grasp, Table 7.1
    object_size: float | None = None  # grasp, metres
    hand_opening: float | None = None  # release, 0 closed .. 1 open
    file: str | None = None  # task: the sub-task's ATD, relative to this file
    parameters: dict[str, str] = Field(default_factory=dict)  # primitive parameter overrides
    object: str | None = None  # which of the task's objects it acts on
    container: str | None = None  # perceive: which of the task's containers it looks in
    method: PerceptionMethod | None = None  # perceive
    direction: Vec3 | None = None  # explore: a unit vector, world frame
    contact_force: float | None = None  # explore: N felt that means contact
    max_distance: float | None = None  # explore: m to go before giving up
    writes: tuple[Value, ...] = ()  # perceptual primitives: the values it produces
    target_from: str | None = None  # arm primitives: the named value that is its target
    target_offset: Vec3 | None = None  # m, world frame: added to the value's position (`<target offset>`)
    top_from: str | None = None  # grasp: the named value whose seen top is the object's (`<object_top from>`)
    inputs: dict[str, str] = Field(default_factory=dict)  # task: sub-task input -> this task's value
    role: str | None = None  # which of the task's arm roles does it; None: the task's only role

    @property
    def target(self) -> Waypoint | None:
        """The last waypoint is where an arm primitive ends."""
        return self.path[-1] if self.path else None

    @property
    def reads(self) -> tuple[str, ...]:
        """The named values the state needs when it starts: its target's, its object's top's,
        its sub-task's inputs'."""
        named = tuple(v for v in (self.target_from, self.top_from) if v)
        return named + tuple(self.inputs.values())


class Role(AtdElement):
    """An arm's part in a task (`holder`, `worker`): the task names the work, never a robot's
    side; the robot's factory binds each role to one of its arms."""

    name: str


class Event(AtdElement):
    type: EventType
    seconds: float | None = None  # only for timeout
    name: str | None = None  # only for outcome: the sub-task's end state

    @property
    def key(self) -> tuple:
        """What the event means: two edges from one state on the same keys cannot both be taken."""
        return (self.type, self.seconds, self.name)

    @property
    def label(self) -> str:
        if self.type is EventType.TIMEOUT:
            return f"timeout({self.seconds:g}s)"
        if self.type is EventType.OUTCOME:
            return f"outcome({self.name})"
        return self.type.value


class Transition(AtdElement):
    """An edge, taken when all its events hold."""

    origin: str
    destination: str
    events: tuple[Event, ...]

    @property
    def label(self) -> str:
        return " & ".join(e.label for e in self.events)


UNNAMED_OBJECT = "object"  # the name of a task's one unnamed object, as the simulator calls it


class KnowsObjects(Frozen):
    """A machine that knows objects: an ATD or the ESTD made from it. `known_objects` keeps
    the file's order, which is the simulator's; `object`, the first, is what a one-object
    task plans with, and `model_copy(update={"object": ...})` replaces it."""

    known_objects: tuple[ObjectInfo, ...] = ()

    @cached_property
    def objects(self) -> dict[str, ObjectInfo]:
        """The objects by name, in the file's order."""
        return {o.name or UNNAMED_OBJECT: o for o in self.known_objects}

    @property
    def object(self) -> ObjectInfo | None:
        return self.known_objects[0] if self.known_objects else None

    def model_copy(self, *, update: dict[str, Any] | None = None, deep: bool = False):  # type: ignore[override]
        """`update={"object": info}` replaces the first object (or adds it), keeping its name."""
        if update and "object" in update:
            update = dict(update)
            one = update.pop("object")
            if one is not None and self.object is not None and self.object.name:
                one = one.model_copy(update={"name": self.object.name})
            update["known_objects"] = tuple(o for o in (one,) if o is not None) + self.known_objects[1:]
        return super().model_copy(update=update, deep=deep)


class Task(AtdElement, KnowsObjects):
    """A whole ATD: the `statemachine` element."""

    initial: str | None = None
    environment: Environment | None = None
    inputs: tuple[Value, ...] = ()  # a sub-task's values the including task gives it
    roles: tuple[Role, ...] = ()  # the arms it needs, by role; none: one arm, the robot's chosen one
    states: tuple[State, ...] = ()
    transitions: tuple[Transition, ...] = ()
    source: str | None = Field(default=None, exclude=True, repr=False)

    @property
    def initial_state(self) -> str | None:
        """`initial="..."` when given, otherwise the first state in document order."""
        if self.initial is not None:
            return self.initial
        return self.states[0].name if self.states else None

    @cached_property
    def states_by_name(self) -> dict[str, State]:
        return {s.name: s for s in self.states}

    @property
    def role_names(self) -> tuple[str, ...]:
        """The roles in file order; a task that declares none has one, unnamed (None)."""
        return tuple(r.name for r in self.roles) or (None,)

    def role_of(self, state: State) -> str | None:
        """The role doing `state`: its own, or the task's first (its only one, where it says none)."""
        return state.role or self.role_names[0]

    @cached_property
    def containers(self) -> dict[str, ContainerInfo]:
        """The containers the task knows, by name."""
        return {c.name: c for c in (self.environment.containers if self.environment else ())}

    @cached_property
    def transition_ids(self) -> tuple[str, ...]:
        """Stable ids for edges: `origin->destination`, with `#n` among parallel edges."""
        totals: dict[tuple[str, str], int] = {}
        for t in self.transitions:
            totals[(t.origin, t.destination)] = totals.get((t.origin, t.destination), 0) + 1
        seen: dict[tuple[str, str], int] = {}
        ids = []
        for t in self.transitions:
            key = (t.origin, t.destination)
            seen[key] = seen.get(key, 0) + 1
            base = f"{t.origin}->{t.destination}"
            ids.append(base if totals[key] == 1 else f"{base}#{seen[key]}")
        return tuple(ids)

    @cached_property
    def edges_leaving(self) -> dict[str, tuple[tuple[str, Transition], ...]]:
        """Each state's edges with their ids, in document order: indexed once, so following
        a chain of thousands of states costs each step a look-up, not a scan."""
        found: dict[str, list[tuple[str, Transition]]] = {}
        for tid, t in zip(self.transition_ids, self.transitions):
            found.setdefault(t.origin, []).append((tid, t))
        return {origin: tuple(edges) for origin, edges in found.items()}

    def outgoing(self, name: str) -> list[tuple[str, Transition]]:
        """The edges leaving a state, each with its id, in document order."""
        return list(self.edges_leaving.get(name, ()))
