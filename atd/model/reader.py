"""From a parsed ATD document to a `Task`, reporting every structural problem at once.

The reader keeps going after a bad element: it drops what it cannot read, says why,
and hands the rest on so that graph checks still run, as a compiler does.
"""

from __future__ import annotations

import itertools
import math
import re
from functools import cache
from enum import StrEnum
from pathlib import Path
from typing import Iterable, TypeVar

from lxml import etree

from atd.model.diagnostics import Diagnostic, did_you_mean, error
import atd.model.ranges as ranges
from atd.model.controllers import CONTROLLERS, parse_value
from atd.model.files import name_too_long
from atd.model.ranges import Range
from atd.model.task import (
    ContainerInfo,
    Environment,
    ObjectInfo,
    Obstacle,
    Pose,
    Role,
    Task,
    Value,
)
from atd.model.vocabulary import (
    PRODUCES,
    SIZE_LAYOUT,
    EventType,
    HandShape,
    Movement,
    ObjectClass,
    PathPoint,
    PerceptionMethod,
    StateType,
    ValueKind,
)
from atd.model.xmlsafe import ParsedXml

E = TypeVar("E", bound=StrEnum)
# The fields of a state, transition, event or waypoint. The reader checks each value itself,
# to report it at its line; pydantic then builds the whole task in one pass of its core,
# three times faster than validating a model per element (issue 12: 140,000 of them in a
# 40,000-state task).
Fields = dict[str, object]

ROOT = "statemachine"
TASK_CHILDREN = ("object", "environment", "input", "role", "state", "transition")
OBJECT_CHILDREN = ("pose", "weight", "inertia", "shape", "friction", "class", "size")
ENVIRONMENT_CHILDREN = ("obstacle", "container")
CONTAINER_CHILDREN = ("pose", "size", "wall")
STATE_CHILDREN = (
    "movement", "hand_shape", "path", "trajectory", "preshape", "object_size", "hand_opening", "parameter",
    "method", "direction", "contact_force", "max_distance", "writes", "target", "input",
    "object_top",
)
STATE_ATTRIBUTES = ("name", "type", "file", "object", "container", "role")
IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
UNIT_TOLERANCE = 1e-3  # how far from 1 the length of a direction may be
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

    def _identifier(self, node: etree._Element, name: str, what: str) -> bool:
        """A name other elements refer to: a plain identifier; a located error when it is not."""
        if IDENTIFIER.fullmatch(name):
            return True
        self._error("ATD113", f"{what} '{name}' is not a plain name", node,
                    "use letters, digits and underscores, starting with a letter or an underscore, e.g. mug_2")
        return False

    def value_declaration(self, node: etree._Element, what: str) -> Value | None:
        """`<writes name="..." kind="..."/>` or a sub-task's `<input name="..." kind="..."/>`."""
        self._check_attributes(node, ("name", "kind"))
        self._no_children(node)
        name, word = node.get("name"), node.get("kind")
        kind = None
        if word is None:
            self._error("ATD102", f"<{node.tag}> has no kind", node,
                        f"add kind=\"...\", one of: {', '.join(k.value for k in ValueKind)}")
        else:
            kind = self._enum(node, ValueKind, "value kind", text=word)
        if not name:
            self._error("ATD102", f"<{node.tag}> has no name", node, f'add name="..." naming the {what}')
            return None
        if not self._identifier(node, name, what) or kind is None:
            return None
        return Value(name=name, kind=kind, loc=self.doc.loc(node))

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
        env = None
        objects: list[ObjectInfo] = []
        inputs: list[Value] = []
        roles: list[Role] = []
        states: list[Fields] = []
        transitions: list[Fields] = []
        for node in _elements(root):
            if node.tag == "object":
                objects.append(self.object(node))
            elif node.tag == "input":
                value = self.value_declaration(node, "input")
                if value is not None:
                    inputs.append(value)
            elif node.tag == "role":
                role = self.role(node)
                if role is not None:
                    roles.append(role)
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
            "known_objects": objects,
            "environment": env,
            "inputs": inputs,
            "roles": roles,
            "states": states,
            "transitions": transitions,
            "source": self.doc.file,
            "loc": self.doc.loc(root),
        })

    def object(self, node: etree._Element) -> ObjectInfo:
        self._check_attributes(node, ("name",))
        seen: dict[str, etree._Element] = {}
        fields: dict = {}
        name = node.get("name")
        if name is not None and self._identifier(node, name, "object name"):
            fields["name"] = name
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

    def role(self, node: etree._Element) -> Role | None:
        """`<role name="holder"/>`: an arm the task needs, named for its part in the task."""
        self._check_attributes(node, ("name",))
        self._no_children(node)
        name = node.get("name")
        if not name:
            self._error("ATD102", "<role> has no name", node,
                        'add name="...", the arm\'s part in the task (e.g. holder, worker); states say role="..."')
            return None
        return Role(name=name, loc=self.doc.loc(node)) if self._identifier(node, name, "role name") else None

    def _size(self, node: etree._Element, kind: ObjectClass | None) -> tuple[float, ...] | None:
        layout = SIZE_LAYOUT[kind or ObjectClass.BOX]
        what = f"size of a {(kind or ObjectClass.BOX).value} ({' '.join(layout)})"
        return self._numbers(node, what, len(layout), ranges.SIZE)

    def environment(self, node: etree._Element) -> Environment:
        self._check_attributes(node, ())
        obstacles = []
        containers = []
        for child in _elements(node):
            if child.tag == "container":
                container = self.container(child)
                if container is not None:
                    containers.append(container)
                continue
            if child.tag != "obstacle":
                self._unknown_element(child, "environment", ENVIRONMENT_CHILDREN)
                continue
            self._check_attributes(child, ("size",))
            position = self._numbers(child, "obstacle position", 3, ranges.COORDINATE)
            size = None
            if "size" in child.attrib:
                size = self._numbers(child, "obstacle size", 3, ranges.SIZE, words=child.get("size", "").split())
            if position is not None:
                obstacles.append(Obstacle(position=position, size=size, loc=self.doc.loc(child)))
        return Environment(obstacles=tuple(obstacles), containers=tuple(containers), loc=self.doc.loc(node))

    def container(self, node: etree._Element) -> ContainerInfo | None:
        """`<container name="box">` with its pose, outer size and wall: an open box the robot knows."""
        self._check_attributes(node, ("name",))
        name = node.get("name")
        if not name:
            self._error("ATD102", "<container> has no name", node, 'add name="..." (states look in it by name)')
        seen: dict[str, etree._Element] = {}
        fields: dict = {}
        for child in _elements(node):
            if child.tag not in CONTAINER_CHILDREN:
                self._unknown_element(child, "container", CONTAINER_CHILDREN)
                continue
            if not self._single(seen, child, "container"):
                continue
            self._check_attributes(child, ())
            if child.tag == "pose":
                fields["pose"] = self._pose(child, "container pose")
            elif child.tag == "size":
                fields["size"] = self._numbers(child, "container size (outer x y z)", 3, ranges.SIZE)
            else:
                fields["wall"] = self._value(child, "container wall", ranges.SIZE)
        for needed, example in (("pose", "<pose>1 0 0 0.3  0 1 0 0  0 0 1 0  0 0 0 1</pose>"),
                                ("size", "<size>0.30 0.25 0.10</size>")):
            if needed not in seen:
                self._error("ATD102", f"<container> '{name}' has no <{needed}>", node, f"add {example}")
        fields = {k: v for k, v in fields.items() if v is not None}
        if not name or not self._identifier(node, name, "container name") or {"pose", "size"} - set(fields):
            return None
        wall = fields.get("wall", ContainerInfo.model_fields["wall"].default)
        size = fields["size"]
        if 2 * wall >= min(size[0], size[1]) or wall >= size[2]:
            self._error("ATD108", f"container '{name}': walls {wall:g} m thick leave no room inside "
                        f"{' x '.join(f'{v:g}' for v in size)} m", seen.get("wall", node),
                        "size is the outer size; give walls thinner than half of it")
            return None
        return ContainerInfo(name=name, **fields, loc=self.doc.loc(node))

    def state(self, node: etree._Element) -> Fields | None:
        self._check_attributes(node, STATE_ATTRIBUTES)
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
        if kind is not None and not self._fits(node, kind, name, fields):
            kind = None
        if name is None or kind is None:
            if name:
                self.dropped_states.add(name)
            return None
        fields.update(name=name, type=kind, file=file if kind is StateType.TASK else None, loc=self.doc.loc(node))
        for attribute in ("object", "container", "role"):
            if node.get(attribute) is not None:
                fields[attribute] = node.get(attribute)
        return fields

    def _fits(self, node: etree._Element, kind: StateType, name: str | None, fields: dict) -> bool:
        """What a state of this type needs and may hold, beyond the common properties: a
        perceive its method and container, an explore its direction; values written only
        by the primitives that produce them; inputs bound only on a sub-task."""
        fine = True
        needs = {StateType.PERCEIVE: (("method", "<method>vision</method>"),),
                 StateType.EXPLORE: (("direction", "<direction>0 0 -1</direction>"),)}.get(kind, ())
        for field, example in needs:
            if field not in fields:
                self._error("ATD102", f"{kind.value} state '{name}' has no <{field}>", node, f"add {example}")
                fine = False
        if kind is StateType.PERCEIVE and node.get("container") is None:
            self._error("ATD102", f"perceive state '{name}' names no container", node,
                        'add container="box", a <container> of the <environment>, to look in')
            fine = False
        only = {"method": StateType.PERCEIVE, "direction": StateType.EXPLORE, "contact_force": StateType.EXPLORE,
                "max_distance": StateType.EXPLORE, "inputs": StateType.TASK}
        for field, owner in only.items():
            if field in fields and kind is not owner:
                what = "<input>" if field == "inputs" else f"<{field}>"
                self._error("ATD103", f"{what} is for {owner.value} states, not type=\"{kind.value}\"", node,
                            f"remove it from state '{name}'")
                fine = False
        if node.get("container") is not None and kind is not StateType.PERCEIVE:
            self._error("ATD103", f"only perceive states look in a container, not type=\"{kind.value}\"", node,
                        'remove container="..."')
            fine = False
        if node.get("object") is not None and (kind.is_end or kind is StateType.TASK):
            self._error("ATD103", f"a {kind.value} state acts on no object", node, 'remove object="..."')
            fine = False
        if node.get("role") is not None and kind.is_end:
            self._error("ATD103", f"a {kind.value} state ends the task and uses no arm", node, 'remove role="..."')
            fine = False
        if "target_from" in fields and not kind.moves_arm:
            self._error("ATD103", f"<target> is for arm primitives, not type=\"{kind.value}\"", node,
                        "an arm primitive (move, transport, place, push, slide) takes its target from a value")
            fine = False
        if "top_from" in fields and kind is not StateType.GRASP:
            self._error("ATD103", f"<object_top> is for grasp states, not type=\"{kind.value}\"", node,
                        "a grasp aims its close at the top a perceive state saw; remove it here")
            fine = False
        produces = PRODUCES.get(kind, frozenset())
        kinds_written: set[ValueKind] = set()
        for value in fields.get("writes", ()):
            if value.kind not in produces:
                can = (f"a {kind.value} state writes a {' or a '.join(sorted(k.value for k in produces))}"
                       if produces else "only perceive (a pose, a count) and explore (a point) states write values")
                self._error("ATD114", f"state '{name}' cannot write a {value.kind.value}", node, can)
                fine = False
            elif value.kind in kinds_written:
                self._error("ATD109", f"state '{name}' writes a {value.kind.value} twice", node, "keep one <writes>")
                fine = False
            kinds_written.add(value.kind)
        return fine

    def _state_properties(self, node: etree._Element) -> dict:
        seen: dict[str, etree._Element] = {}
        fields: dict = {}
        parameters: dict[str, str] = {}
        writes: list[Value] = []
        inputs: dict[str, str] = {}
        for child in _elements(node):
            if child.tag not in STATE_CHILDREN:
                self._unknown_element(child, "state", STATE_CHILDREN)
                continue
            if child.tag == "parameter":
                self._parameter(child, parameters)
                continue
            if child.tag == "writes":
                value = self.value_declaration(child, "value")
                if value is not None:
                    writes.append(value)
                continue
            if child.tag == "input":
                self._binding(child, inputs)
                continue
            key = "path" if child.tag == "trajectory" else str(child.tag)
            if key in seen:
                self._error("ATD109", f"<state> has more than one <{child.tag}>" if key == child.tag
                            else "<state> has both <path> and <trajectory>", child, "keep one")
                continue
            seen[key] = child
            self._check_attributes(child, {"target": ("from", "offset"), "object_top": ("from",),
                                           "path": ("for",)}.get(key, ()))
            if key == "movement":
                fields["movement"] = self._enum(child, Movement, "movement")
            elif key in ("hand_shape", "preshape"):
                fields[key] = self._enum(child, HandShape, "hand shape")
            elif key == "path":
                fields["path"] = self._path(child)
                if child.get("for") is not None:
                    fields["path_for"] = self._enum(child, PathPoint, "point of the hand", text=child.get("for"))
            elif key == "object_size":
                fields["object_size"] = self._value(child, "object size", ranges.SIZE)
            elif key == "hand_opening":
                fields["hand_opening"] = self._value(child, "hand opening", ranges.FRACTION)
            elif key == "method":
                fields["method"] = self._enum(child, PerceptionMethod, "perception method")
            elif key == "direction":
                fields["direction"] = self._direction(child)
            elif key == "contact_force":
                fields["contact_force"] = self._value(child, "contact force", ranges.FORCE)
            elif key == "max_distance":
                fields["max_distance"] = self._value(child, "max distance", ranges.DISTANCE)
            elif key == "target":
                fields["target_from"], fields["target_offset"] = self._target(child)
            elif key == "object_top":
                fields["top_from"] = self._top_from(child)
        if fields.get("path_for") is PathPoint.LOWEST_POINT and "hand_shape" not in seen:
            self._error("ATD102", f"<{seen['path'].tag} for=\"lowest_point\"> needs the state's <hand_shape>: "
                        "the hand's lowest point is that shape's", seen["path"],
                        "add <hand_shape>closed</hand_shape> (or the shape the hand moves in)")
            fields.pop("path_for")
        if "path" in seen and "target" in seen:
            self._error("ATD109", f"<state> has both <{seen['path'].tag}> and <target>", seen["target"],
                        "keep one: a fixed path, or the target a value gives at run time")
            fields.pop("target_from", None)
            fields.pop("target_offset", None)
        if parameters:
            fields["parameters"] = parameters
        if writes:
            fields["writes"] = tuple(writes)
        if inputs:
            fields["inputs"] = inputs
        return {k: v for k, v in fields.items() if v is not None}

    def _direction(self, node: etree._Element) -> tuple[float, ...] | None:
        values = self._numbers(node, "direction", 3, ranges.DIRECTION)
        if values is None:
            return None
        length = math.sqrt(sum(v * v for v in values))
        if abs(length - 1.0) > UNIT_TOLERANCE:
            self._error("ATD108", f"direction is not a unit vector: its length is {length:.4g}", node,
                        "give x y z of length 1 in the world frame, e.g. 0 0 -1 (straight down)")
            return None
        return values

    def _reference(self, node: etree._Element, attribute: str, example: str) -> str | None:
        """The value name an element takes from its `attribute`; located errors when missing or malformed."""
        name = node.get(attribute)
        if not name:
            self._error("ATD102", f"<{node.tag}> has no {attribute}", node, example)
            return None
        return name if self._identifier(node, name, "value name") else None

    def _target(self, node: etree._Element) -> tuple[str | None, tuple[float, ...] | None]:
        """`<target from="approach"/>`: the state's target is a value written by an earlier state;
        `offset="x y z"` (m, world frame) goes that far from it, e.g. a pinch a known depth below
        the top an explore felt."""
        self._no_children(node)
        name = self._reference(node, "from", 'e.g. <target from="approach"/>, naming a value an earlier state writes')
        offset = node.get("offset")
        if offset is None:
            return name, None
        return name, self._numbers(node, "target offset", 3, ranges.COORDINATE, words=offset.split())

    def _top_from(self, node: etree._Element) -> str | None:
        """`<object_top from="approach"/>`: the object's top is the one a perceive state saw,
        read when the grasp starts (the task knows no object; its perception does)."""
        self._no_children(node)
        if (node.text or "").strip():
            self._error("ATD103", "<object_top> holds no number", node,
                        'name the value that gives it at run time: <object_top from="approach"/>')
            return None
        return self._reference(node, "from",
                               'e.g. <object_top from="approach"/>, naming a value a perceive state writes')

    def _binding(self, node: etree._Element, into: dict[str, str]) -> None:
        """`<input name="approach" from="found"/>` on a sub-task state: its input from this task's value."""
        self._check_attributes(node, ("name", "from"))
        self._no_children(node)
        name = node.get("name")
        value = self._reference(node, "from", 'e.g. <input name="approach" from="found"/>')
        if not name:
            self._error("ATD102", "<input> has no name", node, "name the sub-task's <input> it gives a value")
        elif name in into:
            self._error("ATD109", f"input '{name}' is given twice", node, "keep one")
        elif value is not None:
            into[name] = value

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
            self._check_attributes(child, ("name",) if kind is EventType.OUTCOME else ())
            if kind is EventType.TIMEOUT:
                seconds = self._value(child, "timeout", ranges.TIMEOUT)
                if seconds is not None:
                    events.append({"type": kind, "seconds": seconds, "loc": self.doc.loc(child)})
            elif kind is EventType.OUTCOME:
                self._no_children(child)
                name = child.get("name")
                if name:
                    events.append({"type": kind, "name": name, "loc": self.doc.loc(child)})
                else:
                    self._error("ATD102", "<outcome> has no name", child,
                                'name the sub-task\'s end state, e.g. <outcome name="nothing_left"/>')
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

