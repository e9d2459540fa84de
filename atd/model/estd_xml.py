"""ESTD files: XML (the documented format, `schemas/estd.xsd`) and JSON, both ways.

Writing is deterministic, so translating the same task twice gives the same bytes:
parameters are sorted by name and numbers use one fixed format. Reading parses as
safely as an ATD (no entities, no DTD, no network), checks the XSD, then the
vocabulary, and reports problems as diagnostics with file:line.
"""

from __future__ import annotations

import json
from dataclasses import replace
from functools import cache
from pathlib import Path

from lxml import etree
from pydantic import ValidationError

from atd.model.controllers import CONDITIONS, CONTROLLERS, ParamSpec, format_number, format_value, parse_value
from atd.model.diagnostics import Diagnostic, error
from atd.model.files import InputError, read_capped
from atd.model.estd import (
    Condition,
    ConditionGroup,
    Controller,
    Estd,
    EstdEvent,
    EstdState,
    EstdTransition,
    validate_vocabulary,
)
from atd.model.reader import TaskReader
from atd.model.task import Location
from atd.model.writer import environment_element, object_element, value_element
from atd.model.xmlsafe import MAX_BYTES, ParsedXml, parse_bytes, read_file
from schemas import schema_path

ROOT = "estd"


# --- writing ---------------------------------------------------------------------------------


def _attrs(**values: str | None) -> dict[str, str]:
    return {k: v for k, v in values.items() if v is not None}


def _params(node: etree._Element, params: dict) -> None:
    for name in sorted(params):
        etree.SubElement(node, "param", name=name, value=format_value(params[name]))


def _condition(parent: etree._Element, node: Condition | ConditionGroup) -> None:
    if isinstance(node, ConditionGroup):
        group = etree.SubElement(parent, node.op)
        for child in node.children:
            _condition(group, child)
        return
    leaf = etree.SubElement(parent, "condition", _attrs(
        kind=node.kind, sensors=" ".join(node.sensors) or None, atd=node.atd))
    _params(leaf, node.params)


def _machine(parent: etree._Element | None, estd: Estd) -> etree._Element:
    attrs = _attrs(version=str(estd.version), robot=estd.robot, arm=estd.arm, source=estd.source,
                   initial=estd.initial)
    root = etree.Element(ROOT, attrs) if parent is None else etree.SubElement(parent, ROOT, attrs)
    for obj in estd.known_objects:
        object_element(root, obj)
    if estd.environment is not None:
        environment_element(root, estd.environment, format_number)
    for value in estd.inputs:
        value_element(root, "input", value)
    for role, arm in estd.roles.items():
        etree.SubElement(root, "role", name=role, arm=arm)
    for state in estd.states:
        node = etree.SubElement(root, "state", _attrs(
            name=state.name, type=state.type.value, atd=state.atd, loc=state.loc, primitive=state.primitive,
            object=state.object, role=state.role, robot_arm=state.robot_arm, top_from=state.top_from))
        for role, controller in (("arm", state.arm), ("hand", state.hand)):
            if controller is not None:
                _params(etree.SubElement(node, role, controller=controller.name), controller.params)
        if state.target_from is not None:
            offset = {"offset": format_value(state.target_offset)} if state.target_offset else {}
            etree.SubElement(node, "target", {"from": state.target_from, **offset})
        for value in state.writes:
            value_element(node, "writes", value)
        for name, source in state.inputs.items():
            etree.SubElement(node, "input", {"name": name, "from": source})
        if state.machine is not None:
            _machine(node, state.machine)
    for transition in estd.transitions:
        node = etree.SubElement(root, "transition", _attrs(
            origin=transition.origin, destination=transition.destination, atd=transition.atd, loc=transition.loc))
        for event in transition.events:
            _condition(etree.SubElement(node, "event", type=event.type.value, atd=event.atd), event.condition)
    return root


def estd_to_xml(estd: Estd) -> bytes:
    return etree.tostring(_machine(None, estd), pretty_print=True, xml_declaration=True, encoding="UTF-8")


def estd_to_json(estd: Estd) -> bytes:
    data = estd.model_dump(mode="json", exclude_none=True)
    return (json.dumps(data, indent=2, sort_keys=True) + "\n").encode()


# --- reading ---------------------------------------------------------------------------------


@cache
def _schema() -> etree.XMLSchema:
    return etree.XMLSchema(etree.parse(str(schema_path("estd.xsd"))))


class _Problem(Exception):
    def __init__(self, message: str, node: etree._Element) -> None:
        super().__init__(message)
        self.node = node


def _typed_params(node: etree._Element, specs: dict[str, ParamSpec], what: str) -> dict:
    params = {}
    for param in node.iterchildren("param"):
        name = param.get("name")
        if name not in specs:
            raise _Problem(f"{what} has no parameter '{name}'", param)
        try:
            params[name] = parse_value(specs[name], param.get("value", ""))
        except ValueError as exc:
            raise _Problem(f"{what} parameter '{name}': {exc}", param) from None
    return params


def _read_controller(node: etree._Element) -> Controller:
    name = node.get("controller")
    if name not in CONTROLLERS:
        raise _Problem(f"unknown controller '{name}'", node)
    return Controller(name=name, params=_typed_params(node, dict(CONTROLLERS[name].params), f"controller '{name}'"))


def _read_condition(node: etree._Element) -> Condition | ConditionGroup:
    if node.tag in ("all", "any"):
        return ConditionGroup(op=node.tag, children=tuple(_read_condition(c) for c in node.iterchildren(
            "all", "any", "condition")))
    kind = node.get("kind")
    if kind not in CONDITIONS:
        raise _Problem(f"unknown condition kind '{kind}'", node)
    return Condition(kind=kind, sensors=tuple(node.get("sensors", "").split()), atd=node.get("atd", ""),
                     params=_typed_params(node, dict(CONDITIONS[kind].params), f"condition '{kind}'"))


def _offset(target: etree._Element | None) -> tuple[float, ...] | None:
    """A `<target>`'s offset (the schema has made it three numbers), or None."""
    words = target.get("offset") if target is not None else None
    return tuple(float(w) for w in words.split()) if words else None


def _read_machine(node: etree._Element, doc: ParsedXml) -> Estd:
    reader = TaskReader(doc)
    fields: dict = {k: node.get(k) for k in ("robot", "arm", "source", "initial") if node.get(k) is not None}
    fields["version"] = int(node.get("version", "1"))
    states, transitions, objects, inputs, roles = [], [], [], [], {}
    for child in node.iterchildren("object", "environment", "input", "role", "state", "transition"):
        if child.tag == "role":
            roles[child.get("name")] = child.get("arm")
        elif child.tag == "object":
            objects.append(reader.object(child))
        elif child.tag == "environment":
            fields["environment"] = reader.environment(child)
        elif child.tag == "input":
            inputs.append(reader.value_declaration(child, "input"))
        elif child.tag == "state":
            arm, hand, sub, target = child.find("arm"), child.find("hand"), child.find(ROOT), child.find("target")
            states.append(EstdState(
                name=child.get("name"), type=child.get("type"), atd=child.get("atd"), loc=child.get("loc"),
                primitive=child.get("primitive"), object=child.get("object"), role=child.get("role"),
                robot_arm=child.get("robot_arm"), top_from=child.get("top_from"),
                arm=_read_controller(arm) if arm is not None else None,
                hand=_read_controller(hand) if hand is not None else None,
                machine=_read_machine(sub, doc) if sub is not None else None,
                target_from=target.get("from") if target is not None else None,
                target_offset=_offset(target),
                writes=tuple(reader.value_declaration(w, "value") for w in child.iterchildren("writes")),
                inputs={i.get("name"): i.get("from") for i in child.iterchildren("input")}))
        else:
            transitions.append(EstdTransition(
                origin=child.get("origin"), destination=child.get("destination"), atd=child.get("atd"),
                loc=child.get("loc"),
                events=tuple(EstdEvent(type=e.get("type"), atd=e.get("atd"), condition=_read_condition(e[0]))
                             for e in child.iterchildren("event"))))
    if reader.diagnostics:
        first = reader.diagnostics[0]
        raise _Problem(first.message, node)
    return Estd(states=tuple(states), transitions=tuple(transitions), known_objects=tuple(objects),
                inputs=tuple(inputs), roles=roles, **fields)


def parse_estd(data: bytes, file: str) -> tuple[Estd | None, list[Diagnostic]]:
    """An ESTD from XML bytes, or None and the reasons why not."""
    doc, found = parse_bytes(data, file)
    return (None, found) if doc is None else _from_doc(doc)


def _from_doc(doc: ParsedXml) -> tuple[Estd | None, list[Diagnostic]]:
    file = doc.file
    if doc.root.tag != ROOT:
        return None, [error("ESTD101", f"root element is <{doc.root.tag}>, not <{ROOT}>", doc.loc(doc.root),
                            "is this an ATD? translate it first: atd translate FILE --robot R")]
    schema = _schema()
    if not schema.validate(etree.ElementTree(doc.root)):
        return None, [error("ESTD100", f"schema: {e.message}", Location(file, e.line, max(e.column, 1)),
                            "see schemas/estd.xsd and docs/estd.md") for e in schema.error_log]
    try:
        estd = _read_machine(doc.root, doc)
    except _Problem as problem:
        return None, [error("ESTD102", str(problem), doc.loc(problem.node), "see docs/estd.md for the vocabulary")]
    except ValidationError as exc:
        return None, [error("ESTD102", f"invalid ESTD: {exc.errors()[0]['msg']}", doc.loc(doc.root), None)]
    return _checked(estd, file)


def parse_estd_json(data: bytes, file: str) -> tuple[Estd | None, list[Diagnostic]]:
    """An ESTD from JSON bytes, its values checked as those of its XML form are (ranges, rigid
    poses, the vocabulary): JSON's types let through a NaN weight or an infinite pose."""
    try:
        estd = Estd.model_validate_json(data, strict=True)  # JSON true is no number, nor "0.1"
        as_xml = estd_to_xml(estd)
    except ValidationError as exc:
        first = exc.errors()[0]
        where = ".".join(str(p) for p in first["loc"])
        return None, [error("ESTD102", f"invalid ESTD JSON at {where}: {first['msg']}", Location(file, 0, 0),
                            "see docs/estd.md")]
    except ValueError as exc:  # text XML cannot hold, e.g. a control character in a name
        return None, [error("ESTD102", f"invalid ESTD JSON: {exc}", Location(file, 0, 0), "see docs/estd.md")]
    checked, found = parse_estd(as_xml, file)
    if checked is None:  # located in the XML form, which the user never saw: the file alone
        return None, [replace(d, loc=Location(file, 0, 0)) for d in found]
    return estd, []


def _checked(estd: Estd, file: str) -> tuple[Estd | None, list[Diagnostic]]:
    problems = validate_vocabulary(estd)
    if problems:
        return None, [error("ESTD103", p, Location(file, 0, 0), "see docs/estd.md for the vocabulary")
                      for p in problems]
    return estd, []


def is_estd_file(path: str | Path) -> bool:
    """Whether a file holds an ESTD (JSON by its suffix, or XML with an <estd> root) rather
    than an ATD; commands that take either ask this first."""
    path = Path(path)
    if path.suffix == ".json":
        return True
    doc, _ = read_file(path)
    return doc is not None and doc.root.tag == ROOT


def read_estd(path: str | Path) -> tuple[Estd | None, list[Diagnostic]]:
    """Read an ESTD file, XML or (by its `.json` suffix) JSON."""
    path = Path(path)
    if path.suffix != ".json":
        doc, found = read_file(path)
        return (None, found) if doc is None else _from_doc(doc)
    try:
        return parse_estd_json(read_capped(path, MAX_BYTES), str(path))
    except InputError as exc:
        return None, [error("ESTD001", str(exc), Location(str(path), 0, 0), "name an ESTD file (.estd.xml or .json)")]
