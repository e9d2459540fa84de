"""The closed vocabularies of the ATD language (D5 Table 2.1, thesis Tables 7.1 and 7.2).

Every value here is a word a task author may write in a file; `schemas/atd.xsd` lists the
same words and a test keeps the two in step.
"""

from enum import StrEnum


class StateType(StrEnum):
    """What a node of the task graph is: an abstract primitive, a sub-task or an end state."""

    MOVE = "move"
    TRANSPORT = "transport"
    PLACE = "place"
    PUSH = "push"
    GRASP = "grasp"
    RELEASE = "release"
    SLIDE = "slide"
    EXPLORE = "explore"  # perceptual (thesis Table 3.1): move along a direction until contact
    PERCEIVE = "perceive"  # perceptual (thesis 3.4.3): choose an object to grasp, or find none
    UNSCREW = "unscrew"  # thesis 3.3.6: pinch, twist and pull a screwed cap until it comes off
    TASK = "task"
    SUCCESS = "success"
    FAILURE = "failure"

    @property
    def is_end(self) -> bool:
        return self in END_STATES

    @property
    def moves_arm(self) -> bool:
        """Arm primitives take a target (Table 7.1); grasp and release act on the hand only."""
        return self in ARM_PRIMITIVES

    @property
    def acts_on_object(self) -> bool:
        """Primitives that handle an object, and so say which when a task knows several."""
        return self in OBJECT_PRIMITIVES


# Sets, not tuples of members: a member looked up on its class costs a descriptor call, and these
# are asked of every state of a 40,000-state task.
END_STATES = frozenset({StateType.SUCCESS, StateType.FAILURE})
ARM_PRIMITIVES = frozenset(
    {StateType.MOVE, StateType.TRANSPORT, StateType.PLACE, StateType.PUSH, StateType.SLIDE}
)
OBJECT_PRIMITIVES = frozenset(
    {StateType.GRASP, StateType.TRANSPORT, StateType.PLACE, StateType.PUSH, StateType.SLIDE, StateType.UNSCREW}
)
PERCEPTUAL_PRIMITIVES = frozenset({StateType.EXPLORE, StateType.PERCEIVE})


class Movement(StrEnum):
    """How an arm primitive may reach its target (thesis 7.2)."""

    FREE = "free"  # any path
    GUARDED = "guarded"  # straight Cartesian line, stop on contact
    CONSTRAINED = "constrained"  # orientation held during the motion


class PathPoint(StrEnum):
    """Which point of the hand a path's positions are for (`<path for="...">`)."""

    HAND_SHAPE = "hand_shape"  # where the state's hand shape acts: a grasp centre, a pointing fingertip
    LOWEST_POINT = "lowest_point"  # the hand's lowest point in that shape, pads counted, under that point


class HandShape(StrEnum):
    """The 14 hand shapes of D5 2.2.2."""

    OPEN = "open"
    CLOSED = "closed"
    EXTEND = "extend"
    EXTEND_FINGER = "extend_finger"
    POWER_GRASP_PRESHAPE = "power_grasp_preshape"
    POWER_GRASP = "power_grasp"
    PINCH_GRASP_PRESHAPE = "pinch_grasp_preshape"
    PINCH_GRASP = "pinch_grasp"
    CYLINDRICAL_GRASP_PRESHAPE = "cylindrical_grasp_preshape"
    CYLINDRICAL_GRASP = "cylindrical_grasp"
    SPHERICAL_GRASP_PRESHAPE = "spherical_grasp_preshape"
    SPHERICAL_GRASP = "spherical_grasp"
    HOOK_GRASP_PRESHAPE = "hook_grasp_preshape"
    HOOK_GRASP = "hook_grasp"


class EventType(StrEnum):
    """Abstract events that label the edges of the task graph."""

    SUCCESS = "success"
    GRASP_STABLE = "grasp_stable"
    GRASP_LOST = "grasp_lost"
    FINGER_CONTACT = "finger_contact"
    FINGER_CONTACT_LOST = "finger_contact_lost"
    TIMEOUT = "timeout"
    COLLISION = "collision"
    HARDWARE_FAILURE = "hardware_failure"
    ERROR = "error"
    OBJECT_FOUND = "object_found"  # perceive chose an object: its approach is written
    NOTHING_FOUND = "nothing_found"  # perceive found no object where it looked
    OBJECT_IN_HAND = "object_in_hand"  # perceive's hand could not close: something is held between its fingers
    CONTACT = "contact"  # explore felt contact: where is written
    NO_CONTACT = "no_contact"  # explore ended without contact: its whole distance, or stopped short (it says why)
    OUTCOME = "outcome"  # a sub-task ended in the end state it names


class ValueKind(StrEnum):
    """What a named value holds: the data a state passes to later states."""

    POSE = "pose"  # 16 numbers, as a <pose>
    POINT = "point"  # x y z
    COUNT = "count"  # a whole number


class PerceptionMethod(StrEnum):
    """How a perceive state chooses the object to grasp (thesis 3.4.3, Fig. 3.26)."""

    RANDOM_BLIND = "random_blind"  # top approaches drawn uniformly inside the container
    BLIND_EXPLORATION = "blind_exploration"  # down until contact, then sweep the container
    VISION = "vision"  # depth camera: clusters inside the container, one chosen at random


# What each perceptual primitive can write (the kinds a `<writes>` may name), and the event on
# which it has: a value is written only when the state leaves on that event.
PRODUCES: dict[StateType, frozenset[ValueKind]] = {
    StateType.PERCEIVE: frozenset({ValueKind.POSE, ValueKind.COUNT}),
    StateType.EXPLORE: frozenset({ValueKind.POINT}),
}
FINDING_EVENT: dict[StateType, EventType] = {
    StateType.PERCEIVE: EventType.OBJECT_FOUND,
    StateType.EXPLORE: EventType.CONTACT,
}
# Events only some states fire: each with the state types it may leave.
FIRED_BY: dict[EventType, frozenset[StateType]] = {
    EventType.OBJECT_FOUND: frozenset({StateType.PERCEIVE}),
    EventType.NOTHING_FOUND: frozenset({StateType.PERCEIVE}),
    EventType.OBJECT_IN_HAND: frozenset({StateType.PERCEIVE}),
    EventType.CONTACT: frozenset({StateType.EXPLORE}),
    EventType.NO_CONTACT: frozenset({StateType.EXPLORE}),
    EventType.OUTCOME: frozenset({StateType.TASK}),
}
# Where a value may be read, and the kinds each place takes: an arm primitive's target is a
# pose (the hand turned as it says) or a point (the hand top-down).
TARGET_KINDS = frozenset({ValueKind.POSE, ValueKind.POINT})
# A grasp's `<object_top from>` reads a perceive state's approach: the top it saw there.
TOP_KINDS = frozenset({ValueKind.POSE})


class ObjectClass(StrEnum):
    """Geometric class of the target object; decides how `size` is read."""

    BOX = "box"
    CYLINDER = "cylinder"
    SPHERE = "sphere"


# How many numbers `size` holds per class, what they mean, and the default when a file
# gives a class but no size (a 5 cm cube, a 6 cm x 10 cm can, a 6 cm ball).
SIZE_LAYOUT: dict[ObjectClass, tuple[str, ...]] = {
    ObjectClass.BOX: ("x", "y", "z"),
    ObjectClass.CYLINDER: ("radius", "height"),
    ObjectClass.SPHERE: ("radius",),
}
DEFAULT_SIZE: dict[ObjectClass, tuple[float, ...]] = {
    ObjectClass.BOX: (0.05, 0.05, 0.05),
    ObjectClass.CYLINDER: (0.03, 0.10),
    ObjectClass.SPHERE: (0.03,),
}
