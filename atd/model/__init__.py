"""The ATD and ESTD languages as data, their XML form, and their validation."""

from atd.model.diagnostics import Diagnostic, Severity, has_errors
from atd.model.load import load_task
from atd.model.task import (
    Environment,
    Event,
    Location,
    Obstacle,
    ObjectInfo,
    Pose,
    Role,
    State,
    Task,
    Transition,
    Waypoint,
)
from atd.model.vocabulary import EventType, HandShape, Movement, ObjectClass, StateType
from atd.model.writer import replacing, task_to_xml, write_atomically

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
    "Role",
    "Severity",
    "State",
    "StateType",
    "Task",
    "Transition",
    "Waypoint",
    "has_errors",
    "load_task",
    "task_to_xml",
    "replacing",
    "write_atomically",
]
