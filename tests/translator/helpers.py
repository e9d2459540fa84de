"""Shared helpers for translator and factory tests: every robot and arm, and small tasks."""

from __future__ import annotations

from atd.model import Event, EventType, ObjectInfo, Pose, State, StateType, Task, Transition, Waypoint
from factories.base import Factory
from factories.registry import BUILTIN, factory_class

BOX = ObjectInfo(pose=Pose.from_position((0.10, -0.05, 0.025)), object_class="box", size=(0.05, 0.05, 0.05))


def every_factory() -> list[Factory]:
    """One factory per built-in robot and arm."""
    return [factory_class(name)(arm=arm.name) for name in sorted(BUILTIN) for arm in factory_class(name).arms]


def at(*xyz: float) -> tuple[Waypoint, ...]:
    return (Waypoint(kind="position", values=xyz),)


def one_state_task(state: State, *events: Event, obj: ObjectInfo | None = BOX) -> Task:
    """`state` then success, with one edge on `events` (default: success)."""
    return Task(known_objects=(obj,) if obj else (), states=(state, State(name="done", type=StateType.SUCCESS)),
                transitions=(Transition(origin=state.name, destination="done",
                                        events=events or (Event(type=EventType.SUCCESS),)),))
