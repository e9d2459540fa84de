"""Writing a `Task` back to ATD XML, in the canonical element order.

Numbers are written with `repr`, the shortest text that reads back to the same float,
so parse -> write -> parse gives an equal task.
"""

from __future__ import annotations

import os
import tempfile
from contextlib import contextmanager
from enum import Enum
from pathlib import Path
from typing import Callable, Iterator

from lxml import etree

from atd.model.task import Environment, ObjectInfo, State, Task, Transition, Value
from atd.model.vocabulary import EventType, PathPoint


def _number(value: float) -> str:
    return repr(float(value))


def _numbers(values: tuple[float, ...]) -> str:
    return " ".join(map(_number, values))


def _optional(node: etree._Element, state: State, *tags: str) -> None:
    """One element per field of the state that is set, named as the field, in the order given:
    a word (an enum's value), numbers, or one number as repr writes it (read back exactly)."""
    for tag in tags:
        value = getattr(state, tag)
        if value is not None:
            text = value.value if isinstance(value, Enum) else _numbers(value) if isinstance(value, tuple) else repr(value)
            _child(node, tag, text)


def _child(parent: etree._Element, tag: str, text: str | None = None, **attrib: str) -> etree._Element:
    node = etree.SubElement(parent, tag, attrib)
    node.text = text
    return node


def object_element(parent: etree._Element, obj: ObjectInfo) -> None:
    """The `<object>` block; ESTD files carry the same block as the ATD they came from."""
    node = _child(parent, "object", **({"name": obj.name} if obj.name else {}))
    if obj.pose is not None:
        _child(node, "pose", _numbers(obj.pose.matrix))
    if obj.weight is not None:
        _child(node, "weight", repr(obj.weight))
    if obj.inertia is not None:
        _child(node, "inertia", _numbers(obj.inertia))
    if obj.shape is not None:
        _child(node, "shape", obj.shape)
    if obj.friction is not None:
        _child(node, "friction", repr(obj.friction))
    if obj.object_class is not None:
        _child(node, "class", obj.object_class.value)
    if obj.size is not None:
        _child(node, "size", _numbers(obj.size))


def environment_element(parent: etree._Element, env: Environment, number: Callable[[float], str] = _number) -> None:
    """The `<environment>` block, numbers written by `number`; ESTD files carry it too."""
    node = _child(parent, "environment")
    for obstacle in env.obstacles:
        attrib = {"size": " ".join(map(number, obstacle.size))} if obstacle.size else {}
        _child(node, "obstacle", " ".join(map(number, obstacle.position)), **attrib)
    for container in env.containers:
        box = _child(node, "container", name=container.name)
        _child(box, "pose", " ".join(map(number, container.pose.matrix)))
        _child(box, "size", " ".join(map(number, container.size)))
        _child(box, "wall", number(container.wall))


def value_element(parent: etree._Element, tag: str, value: Value) -> None:
    """`<writes>` of a state or `<input>` of a sub-task: a named value and its kind."""
    _child(parent, tag, name=value.name, kind=value.kind.value)


def _state(parent: etree._Element, state: State) -> None:
    attrib = {"name": state.name, "type": state.type.value}
    for key in ("file", "object", "container", "role"):
        if getattr(state, key) is not None:
            attrib[key] = getattr(state, key)
    node = _child(parent, "state", **attrib)
    _optional(node, state, "movement", "hand_shape")
    if state.path:
        which = {} if state.path_for is PathPoint.HAND_SHAPE else {"for": state.path_for.value}
        path = _child(node, "path", **which)
        for point in state.path:
            _child(path, point.kind, _numbers(point.values))
    _optional(node, state, "preshape", "object_size", "hand_opening")
    if state.target_from is not None:
        offset = {"offset": _numbers(state.target_offset)} if state.target_offset is not None else {}
        _child(node, "target", **{"from": state.target_from}, **offset)
    if state.top_from is not None:
        _child(node, "object_top", **{"from": state.top_from})
    _optional(node, state, "method", "direction", "contact_force", "max_distance")
    for name, value in state.parameters.items():
        _child(node, "parameter", value, name=name)
    for value in state.writes:
        value_element(node, "writes", value)
    for name, source in state.inputs.items():
        _child(node, "input", name=name, **{"from": source})


def _transition(parent: etree._Element, transition: Transition) -> None:
    node = _child(parent, "transition", origin=transition.origin, destination=transition.destination)
    for event in transition.events:
        seconds = repr(event.seconds) if event.type is EventType.TIMEOUT else None
        _child(node, event.type.value, seconds, **({"name": event.name} if event.name is not None else {}))


def task_to_xml(task: Task) -> bytes:
    root = etree.Element("statemachine", {"initial": task.initial} if task.initial else {})
    for obj in task.known_objects:
        object_element(root, obj)
    if task.environment is not None:
        environment_element(root, task.environment)
    for value in task.inputs:
        value_element(root, "input", value)
    for role in task.roles:
        _child(root, "role", name=role.name)
    for state in task.states:
        _state(root, state)
    for transition in task.transitions:
        _transition(root, transition)
    return etree.tostring(root, pretty_print=True, xml_declaration=True, encoding="UTF-8")


@contextmanager
def replacing(path: Path) -> Iterator[Path]:
    """A temporary file beside `path` that replaces it, readable by all, when the block ends
    without error, and is removed when it does not: a crash never leaves half a file behind."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name[:32]}.", suffix=".tmp", dir=path.parent or ".")
    os.close(fd)
    try:
        yield Path(tmp)
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def write_atomically(path: Path, data: bytes) -> None:
    """Replace `path` in one step with `data`."""
    with replacing(path) as tmp, tmp.open("wb") as out:
        out.write(data)
        out.flush()
        os.fsync(out.fileno())
