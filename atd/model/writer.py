"""Writing a `Task` back to ATD XML, in the canonical element order.

Numbers are written with `repr`, the shortest text that reads back to the same float,
so parse -> write -> parse gives an equal task.
"""

from __future__ import annotations

import os
import tempfile
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator

from lxml import etree

from atd.model.task import ObjectInfo, State, Task, Transition
from atd.model.vocabulary import EventType


def _numbers(values: tuple[float, ...]) -> str:
    return " ".join(repr(float(v)) for v in values)


def _child(parent: etree._Element, tag: str, text: str | None = None, **attrib: str) -> etree._Element:
    node = etree.SubElement(parent, tag, attrib)
    node.text = text
    return node


def object_element(parent: etree._Element, obj: ObjectInfo) -> None:
    """The `<object>` block; ESTD files carry the same block as the ATD they came from."""
    node = _child(parent, "object")
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


def _state(parent: etree._Element, state: State) -> None:
    attrib = {"name": state.name, "type": state.type.value}
    if state.file is not None:
        attrib["file"] = state.file
    node = _child(parent, "state", **attrib)
    if state.movement is not None:
        _child(node, "movement", state.movement.value)
    if state.hand_shape is not None:
        _child(node, "hand_shape", state.hand_shape.value)
    if state.path:
        path = _child(node, "path")
        for point in state.path:
            _child(path, point.kind, _numbers(point.values))
    if state.preshape is not None:
        _child(node, "preshape", state.preshape.value)
    if state.object_size is not None:
        _child(node, "object_size", repr(state.object_size))
    if state.hand_opening is not None:
        _child(node, "hand_opening", repr(state.hand_opening))
    for name, value in state.parameters.items():
        _child(node, "parameter", value, name=name)


def _transition(parent: etree._Element, transition: Transition) -> None:
    node = _child(parent, "transition", origin=transition.origin, destination=transition.destination)
    for event in transition.events:
        seconds = repr(event.seconds) if event.type is EventType.TIMEOUT else None
        _child(node, event.type.value, seconds)


def task_to_xml(task: Task) -> bytes:
    root = etree.Element("statemachine", {"initial": task.initial} if task.initial else {})
    if task.object is not None:
        object_element(root, task.object)
    if task.environment is not None:
        env = _child(root, "environment")
        for obstacle in task.environment.obstacles:
            attrib = {"size": _numbers(obstacle.size)} if obstacle.size else {}
            _child(env, "obstacle", _numbers(obstacle.position), **attrib)
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
