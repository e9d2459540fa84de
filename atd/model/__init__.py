"""The ATD and ESTD languages as data, their XML form, and their validation."""

from atd.model.diagnostics import Diagnostic, Severity, has_errors
from atd.model.task import (
    Environment,
    Event,
    Location,
    Obstacle,
    ObjectInfo,
    Pose,
    State,
    Task,
    Transition,
    Waypoint,
)
from atd.model.vocabulary import EventType, HandShape, Movement, ObjectClass, StateType

__all__ = [
    "Diagnostic",
    "Environment",
    "Event",
    "EventType",
    "HandShape",
    "Location",
    "Movement",
    "ObjectClass",
    "ObjectInfo",
    "Obstacle",
    "Pose",
    "Severity",
    "State",
    "StateType",
    "Task",
    "Transition",
    "Waypoint",
    "has_errors",
]
