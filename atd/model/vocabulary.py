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


# Sets, not tuples of members: a member looked up on its class costs a descriptor call, and these
# are asked of every state of a 40,000-state task.
END_STATES = frozenset({StateType.SUCCESS, StateType.FAILURE})
ARM_PRIMITIVES = frozenset(
    {StateType.MOVE, StateType.TRANSPORT, StateType.PLACE, StateType.PUSH, StateType.SLIDE}
)


class Movement(StrEnum):
    """How an arm primitive may reach its target (thesis 7.2)."""

    FREE = "free"  # any path
    GUARDED = "guarded"  # straight Cartesian line, stop on contact
    CONSTRAINED = "constrained"  # orientation held during the motion


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
