"""From a parsed ATD document to a `Task`, reporting every structural problem at once.

The reader keeps going after a bad element: it drops what it cannot read, says why,
and hands the rest on so that graph checks still run, as a compiler does.
"""

from __future__ import annotations

import itertools
import math
from functools import cache
from enum import StrEnum
from pathlib import Path
from typing import Iterable, TypeVar

from lxml import etree

from atd.model.diagnostics import Diagnostic, did_you_mean, error
from atd.model import ranges
from atd.model.controllers import CONTROLLERS, parse_value
from atd.model.files import name_too_long
from atd.model.ranges import Range
from atd.model.task import (
    Environment,
    ObjectInfo,
    Obstacle,
    Pose,
    Task,
)
from atd.model.vocabulary import (
    SIZE_LAYOUT,
    EventType,
    HandShape,
    Movement,
    ObjectClass,
    StateType,
)
from atd.model.xmlsafe import ParsedXml

E = TypeVar("E", bound=StrEnum)
# The fields of a state, transition, event or waypoint. The reader checks each value itself,
# to report it at its line; pydantic then builds the whole task in one pass of its core,
# three times faster than validating a model per element (issue 12: 140,000 of them in a
# 40,000-state task).
Fields = dict[str, object]

ROOT = "statemachine"
TASK_CHILDREN = ("object", "environment", "state", "transition")
OBJECT_CHILDREN = ("pose", "weight", "inertia", "shape", "friction", "class", "size")
STATE_CHILDREN = (
    "movement", "hand_shape", "path", "trajectory", "preshape", "object_size", "hand_opening", "parameter",
)
WAYPOINTS = ("position", "pose", "point")
WAYPOINT_COUNT = {"position": 3, "pose": 16, "point": 3}
RIGID_TOLERANCE = 1e-3


def _elements(node: etree._Element) -> list[etree._Element]:
    """Child elements: the parser keeps neither comments nor processing instructions, and a
    slice is three times cheaper than filtering them out (a 40,000-state task has 160,000 elements)."""
    return node[:]


def _words(node: etree._Element) -> list[str]:
    return (node.text or "").split()


def is_rigid(matrix: tuple[float, ...]) -> bool:
    """A row-major 4x4 whose rotation block is orthonormal with determinant +1 and whose bottom
    row is 0 0 0 1. In plain Python: reading a task needs no numpy, which would double the start-up
    time of `atd validate`."""
    rows = (matrix[0:3], matrix[4:7], matrix[8:11])
    columns = tuple(zip(*rows))
    orthonormal = all(abs(sum(a * b for a, b in zip(columns[i], columns[j])) - (i == j)) <= RIGID_TOLERANCE
                      for i in range(3) for j in range(3))
    (a, b, c), (d, e, f), (g, h, k) = rows
    determinant = a * (e * k - f * h) - b * (d * k - f * g) + c * (d * h - e * g)
    bottom = all(abs(v - w) <= RIGID_TOLERANCE for v, w in zip(matrix[12:16], (0, 0, 0, 1)))
    return orthonormal and abs(determinant - 1.0) < RIGID_TOLERANCE and bottom


class TaskReader:
    """Reads one document; collects diagnostics in `self.diagnostics`."""

    def __init__(self, doc: ParsedXml) -> None:
        self.doc = doc
        self.diagnostics: list[Diagnostic] = []
        self.dropped_states: set[str] = set()  # named in the file but unreadable

    # -- reporting ---------------------------------------------------------------------
    def _error(self, code: str, message: str, node: etree._Element, hint: str | None = None) -> None:
        self.diagnostics.append(error(code, message, self.doc.loc(node), hint))

    def _unknown_element(self, node: etree._Element, parent: str, allowed: Iterable[str]) -> None:
        allowed = list(allowed)
        self._error(
            "ATD101",
            f"unknown element <{node.tag}> in <{parent}>",
            node,
            did_you_mean(str(node.tag), allowed) or f"<{parent}> holds: {', '.join(allowed)}",
        )

    def _check_attributes(self, node: etree._Element, allowed: tuple[str, ...]) -> None:
        for name in node.keys():
            if name not in allowed:
                hint = did_you_mean(name, allowed) or (
                    f"<{node.tag}> takes {', '.join(allowed)}" if allowed else f"<{node.tag}> takes no attributes"
                )
                self._error("ATD103", f"unknown attribute '{name}' on <{node.tag}>", node, hint)

    def _no_children(self, node: etree._Element) -> None:
        if not len(node):  # most elements: no child node at all, answered without listing them
            return
        for child in _elements(node):
            self._error("ATD101", f"unexpected element <{child.tag}> inside <{node.tag}>", child,
                        f"<{node.tag}> holds only text")

    # -- values ------------------------------------------------------------------------
    def _enum(self, node: etree._Element, enum: type[E], what: str, text: str | None = None) -> E | None:
        if text is None:
            self._no_children(node)
        word = (node.text or "").strip() if text is None else text
        member = _members(enum).get(word)
        if member is None:
            names = list(_members(enum))
            self._error(
                "ATD104",
                f"'{word}' is not {'an' if what[0] in 'aeiou' else 'a'} {what}" if word else f"empty {what}",
                node,
                did_you_mean(word, names) or f"use one of: {', '.join(names)}",
            )
        return member

    def _numbers(self, node: etree._Element, what: str, count: int | None, allowed: Range,
                 words: list[str] | None = None) -> tuple[float, ...] | None:
        """The numbers of an element, each checked against its declared range."""
        self._no_children(node)
        words = _words(node) if words is None else words
        try:
            values = ranges.numbers(words)
        except ValueError as exc:
            self._error("ATD106", f"{exc} in {what}", node,
                        "write numbers in metres, kilograms and seconds, e.g. 0.25")
            return None
        infinite = next(itertools.filterfalse(math.isfinite, values), None)
        if infinite is not None:
            self._error("ATD106", f"{what}: {allowed.problem(infinite)}",
                        node, "use finite numbers")
            return None
        if count is not None and len(values) != count:
            self._error("ATD105", f"{what} needs {count} number{'s' * (count != 1)}, found {len(values)}", node,
                        _count_hint(what, count))
            return None
        problem = allowed.first_problem(values)
        if problem:
            self._error("ATD108", f"{what}: {problem}", node, f"give {what} in {allowed}")
            return None
        return values

    def _value(self, node: etree._Element, what: str, allowed: Range) -> float | None:
        values = self._numbers(node, what, 1, allowed)
        return values[0] if values else None

    def _pose(self, node: etree._Element, what: str = "pose") -> Pose | None:
        values = self._numbers(node, what, 16, ranges.COORDINATE)
        if values is None:
            return None
        if not is_rigid(values):
            self._error(
                "ATD107",
                f"{what} is not a rigid transform",
                node,
                "16 numbers, row-major 4x4: an orthonormal rotation (det +1), translation in the last "
                "column, last row 0 0 0 1; identity at (1,1,1) is 1 0 0 1 0 1 0 1 0 0 1 1 0 0 0 1",
            )
            return None
        return Pose(matrix=values, loc=self.doc.loc(node))

    def _file_name(self, node: etree._Element, name: str, what: str) -> bool:
        """A file name a file system can hold; a located error when it is not."""
        problem = name_too_long(Path(name))
        if problem:
            self._error("ATD112", f"{what}: {problem}", node, "rename the file and this reference")
        return problem is None

    def _single(self, seen: dict[str, etree._Element], node: etree._Element, parent: str) -> bool:
        """True the first time a property appears; a repeat is reported."""
        if node.tag in seen:
            first = self.doc.loc(seen[node.tag])
            self._error("ATD109", f"<{parent}> has more than one <{node.tag}>", node,
                        f"the first one is at line {first.line}; keep one")
            return False
        seen[str(node.tag)] = node
        return True

    # -- elements ----------------------------------------------------------------------
    def task(self) -> Task | None:
        root = self.doc.root
        if root.tag != ROOT:
            self._error("ATD110", f"the root element is <{root.tag}>, not <{ROOT}>", root,
                        f"an ATD is one <{ROOT}> element holding objects, states and transitions")
            return None
        self._check_attributes(root, ("initial",))
        seen: dict[str, etree._Element] = {}
        obj = env = None
        states: list[Fields] = []
        transitions: list[Fields] = []
        for node in _elements(root):
            if node.tag == "object" and self._single(seen, node, ROOT):
                obj = self.object(node)
            elif node.tag == "environment" and self._single(seen, node, ROOT):
                env = self.environment(node)
            elif node.tag == "state":
                state = self.state(node)
                if state is not None:
                    states.append(state)
            elif node.tag == "transition":
                transition = self.transition(node)
                if transition is not None:
                    transitions.append(transition)
            elif node.tag not in TASK_CHILDREN:
                self._unknown_element(node, ROOT, TASK_CHILDREN)
        return Task.model_validate({
            "initial": root.get("initial"),
            "object": obj,
            "environment": env,
            "states": states,
            "transitions": transitions,
            "source": self.doc.file,
            "loc": self.doc.loc(root),
        })

    def object(self, node: etree._Element) -> ObjectInfo:
        self._check_attributes(node, ())
        seen: dict[str, etree._Element] = {}
        fields: dict = {}
        for child in _elements(node):
            if child.tag not in OBJECT_CHILDREN:
                self._unknown_element(child, "object", OBJECT_CHILDREN)
                continue
            if not self._single(seen, child, "object"):
                continue
            self._check_attributes(child, ())
            if child.tag == "pose":
                fields["pose"] = self._pose(child, "object pose")
            elif child.tag == "weight":
                fields["weight"] = self._value(child, "weight", ranges.WEIGHT)
            elif child.tag == "inertia":
                fields["inertia"] = self._numbers(child, "inertia", 9, ranges.INERTIA)
            elif child.tag == "friction":
                fields["friction"] = self._value(child, "friction", ranges.FRICTION)
            elif child.tag == "shape":
                self._no_children(child)
                fields["shape"] = (child.text or "").strip() or None
                if fields["shape"] is None:
                    self._error("ATD105", "empty <shape>", child, "name a mesh file next to the ATD, e.g. cup.stl")
                elif not self._file_name(child, fields["shape"], "shape"):
                    fields["shape"] = None
            elif child.tag == "class":
                fields["object_class"] = self._enum(child, ObjectClass, "object class")
        if "size" in seen:
            fields["size"] = self._size(seen["size"], fields.get("object_class"))
        return ObjectInfo(**{k: v for k, v in fields.items() if v is not None}, loc=self.doc.loc(node))

    def _size(self, node: etree._Element, kind: ObjectClass | None) -> tuple[float, ...] | None:
        layout = SIZE_LAYOUT[kind or ObjectClass.BOX]
        what = f"size of a {(kind or ObjectClass.BOX).value} ({' '.join(layout)})"
        return self._numbers(node, what, len(layout), ranges.SIZE)

    def environment(self, node: etree._Element) -> Environment:
        self._check_attributes(node, ())
        obstacles = []
        for child in _elements(node):
            if child.tag != "obstacle":
                self._unknown_element(child, "environment", ("obstacle",))
                continue
            self._check_attributes(child, ("size",))
            position = self._numbers(child, "obstacle position", 3, ranges.COORDINATE)
            size = None
            if "size" in child.attrib:
                size = self._numbers(child, "obstacle size", 3, ranges.SIZE, words=child.get("size", "").split())
            if position is not None:
                obstacles.append(Obstacle(position=position, size=size, loc=self.doc.loc(child)))
        return Environment(obstacles=tuple(obstacles), loc=self.doc.loc(node))

    def state(self, node: etree._Element) -> Fields | None:
        self._check_attributes(node, ("name", "type", "file"))
        name, word, file = node.get("name"), node.get("type"), node.get("file")
        if not name:
            self._error("ATD102", "<state> has no name", node, 'add name="..." (unique within the task)')
        kind = None
        if word is None:
            self._error("ATD102", f"state '{name}' has no type", node,
                        f"add type=\"...\", one of: {', '.join(t.value for t in StateType)}")
        else:
            kind = self._enum(node, StateType, "state type", text=word)
        if kind is StateType.TASK and not file:
            self._error("ATD102", f"task state '{name}' names no file", node,
                        'add file="sub_task.xml", relative to this file')
        if kind is not None and kind is not StateType.TASK and file is not None:
            self._error("ATD103", f"only type=\"task\" states take a file, not type=\"{kind.value}\"", node,
                        'remove file="..." or set type="task"')
        fields = self._state_properties(node)
        if file and not self._file_name(node, file, "file"):
            kind = None
        if name is None or kind is None:
            if name:
                self.dropped_states.add(name)
            return None
        fields.update(name=name, type=kind, file=file if kind is StateType.TASK else None, loc=self.doc.loc(node))
        return fields

    def _state_properties(self, node: etree._Element) -> dict:
        seen: dict[str, etree._Element] = {}
        fields: dict = {}
        parameters: dict[str, str] = {}
        for child in _elements(node):
            if child.tag not in STATE_CHILDREN:
                self._unknown_element(child, "state", STATE_CHILDREN)
                continue
            if child.tag == "parameter":
                self._parameter(child, parameters)
                continue
            key = "path" if child.tag == "trajectory" else str(child.tag)
            if key in seen:
                self._error("ATD109", f"<state> has more than one <{child.tag}>" if key == child.tag
                            else "<state> has both <path> and <trajectory>", child, "keep one")
                continue
            seen[key] = child
            self._check_attributes(child, ())
            if key == "movement":
                fields["movement"] = self._enum(child, Movement, "movement")
            elif key in ("hand_shape", "preshape"):
                fields[key] = self._enum(child, HandShape, "hand shape")
            elif key == "path":
                fields["path"] = self._path(child)
            elif key == "object_size":
                fields["object_size"] = self._value(child, "object size", ranges.SIZE)
            elif key == "hand_opening":
                fields["hand_opening"] = self._value(child, "hand opening", ranges.FRACTION)
        if parameters:
            fields["parameters"] = parameters
        return {k: v for k, v in fields.items() if v is not None}

    def _parameter(self, node: etree._Element, into: dict[str, str]) -> None:
        self._check_attributes(node, ("name",))
        self._no_children(node)
        name = node.get("name")
        if not name:
            self._error("ATD102", "<parameter> has no name", node, 'e.g. <parameter name="force_threshold">5</parameter>')
        elif name in into:
            self._error("ATD109", f"parameter '{name}' is set twice", node, "keep one")
        else:
            into[name] = " ".join(_words(node))
            self._parameter_value(node, name, into[name])

    def _parameter_value(self, node: etree._Element, name: str, text: str) -> None:
        """A value no controller taking this parameter accepts is an error here, at its line,
        not a surprise in the run; which controller takes it is the robot's business."""
        specs = [c.params[name] for c in CONTROLLERS.values() if name in c.params and c.params[name].tunable]
        problems = []
        for spec in specs:
            try:
                parse_value(spec, text)
                return
            except ValueError as exc:
                problems.append(str(exc))
        if problems:
            self._error("ATD108", f"parameter '{name}': {problems[0]}", node,
                        f"see docs/estd.md for what '{name}' means and its unit")

    def _path(self, node: etree._Element) -> list[Fields] | None:
        points = []
        for child in _elements(node):
            if child.tag not in WAYPOINTS:
                self._unknown_element(child, str(node.tag), WAYPOINTS)
                continue
            self._check_attributes(child, ())
            if child.tag == "pose":
                pose = self._pose(child, "waypoint pose")
                values = pose.matrix if pose else None
            else:
                values = self._numbers(child, f"<{child.tag}>", WAYPOINT_COUNT[str(child.tag)], ranges.COORDINATE)
            if values is not None:
                points.append({"kind": child.tag, "values": values, "loc": self.doc.loc(child)})
        if not points and not _elements(node):
            self._error("ATD105", f"empty <{node.tag}>", node, "add <position>x y z</position> waypoints, or remove it")
        return points or None

    def transition(self, node: etree._Element) -> Fields | None:
        self._check_attributes(node, ("origin", "destination"))
        ends = {"origin": node.get("origin"), "destination": node.get("destination")}
        for end, name in ends.items():
            if not name:
                self._error("ATD102", f"<transition> has no {end}", node, f'add {end}="state name"')
        events = []
        children = _elements(node)
        for child in children:
            kind = _members(EventType).get(child.tag)
            if kind is None:
                self._unknown_element(child, "transition", list(_members(EventType)))
                continue
            self._check_attributes(child, ())
            if kind is EventType.TIMEOUT:
                seconds = self._value(child, "timeout", ranges.TIMEOUT)
                if seconds is not None:
                    events.append({"type": kind, "seconds": seconds, "loc": self.doc.loc(child)})
            else:
                self._no_children(child)
                if (child.text or "").strip():
                    self._error("ATD111", f"<{kind.value}/> takes no content", child,
                                "only <timeout> holds a value (seconds)")
                events.append({"type": kind, "loc": self.doc.loc(child)})
        if not children:
            self._error("ATD203", "transition has no event", node,
                        "add at least one event, e.g. <success/>; several events must all hold")
        if not (ends["origin"] and ends["destination"]) or not events:
            return None
        return {"origin": ends["origin"], "destination": ends["destination"], "events": events,
                "loc": self.doc.loc(node)}


@cache
def _members(enum: type[E]) -> dict[str, E]:
    """An enum's members by value: a dict lookup, where calling the enum costs a Python-level
    call and an exception for every word that is not a member."""
    return {member.value: member for member in enum}


def _count_hint(what: str, count: int) -> str:
    if count == 16:
        return "a pose is a row-major 4x4 matrix: 16 numbers"
    if count == 3:
        return "a position is x y z in metres"
    if count == 9:
        return "inertia is a row-major 3x3 matrix: 9 numbers"
    return f"give {count} numbers"


def read_task(doc: ParsedXml) -> tuple[Task | None, list[Diagnostic], set[str]]:
    """Read a parsed document: the task, what was wrong, and names of unreadable states."""
    reader = TaskReader(doc)
    task = reader.task()
    return task, reader.diagnostics, reader.dropped_states

