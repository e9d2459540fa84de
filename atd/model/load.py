"""The one way into a task file: safe parse, read, schema backstop, graph checks, sub-tasks."""

from __future__ import annotations

from functools import cache
from pathlib import Path

from lxml import etree

from atd.model.bulk import cyclic_gc_paused
from atd.model.diagnostics import Diagnostic, error, has_errors, warning
from atd.model.files import unreadable
from atd.model.reader import read_task
from atd.model.task import Location, State, Task
from atd.model.validate import check_task, subtask_path, value_kinds
from atd.model.vocabulary import EventType, StateType
from atd.model.xmlsafe import ParsedXml, read_file
from schemas import schema_path


@cache
def _atd_schema() -> etree.XMLSchema:
    return etree.XMLSchema(etree.parse(str(schema_path("atd.xsd"))))


def schema_check(doc: ParsedXml) -> list[Diagnostic]:
    """The XSD as a backstop: anything the reader let through but the schema refuses."""
    schema = _atd_schema()
    if schema.validate(etree.ElementTree(doc.root)):
        return []
    return [
        error("ATD100", f"schema: {e.message}", Location(doc.file, e.line, max(e.column, 1)),
              "see schemas/atd.xsd and docs/atd-format.md")
        for e in schema.error_log
    ]


def load_task(path: str | Path) -> tuple[Task | None, list[Diagnostic]]:
    """Read and check a task and, recursively, the sub-tasks it includes.

    Returns the task (None when the file could not be read at all) and every
    diagnostic found; the task is fit to translate only when none is an error.
    """
    with cyclic_gc_paused():
        return _load(Path(path), (), {})


Loaded = dict[Path, tuple[Task | None, list[Diagnostic]]]  # sub-tasks read so far, by resolved path


def _load(path: Path, including: tuple[Path, ...], seen: Loaded) -> tuple[Task | None, list[Diagnostic]]:
    doc, found = read_file(path)
    if doc is None:
        return None, found
    task, read_problems, unreadable = read_task(doc)
    found += read_problems
    if task is None:
        return None, found
    read_cleanly = not has_errors(found)
    if read_cleanly:
        found += schema_check(doc)
    found += check_task(task, frozenset(unreadable), read_cleanly)
    found += _check_subtasks(task, including + (path.resolve(),), seen)
    return task, found


def _check_subtasks(task: Task, including: tuple[Path, ...], seen: Loaded) -> list[Diagnostic]:
    found: list[Diagnostic] = []
    for state in task.states:
        if state.type is not StateType.TASK or not state.file:
            continue
        sub = subtask_path(task, state)
        problem = unreadable(sub)
        if problem:
            found.append(error("ATD211", f"sub-task file '{state.file}' of state '{state.name}': {problem}",
                               state.loc, f"looked for {sub}; paths are relative to the including file"))
        elif sub.resolve() in including:
            what = "itself" if sub.resolve() == including[-1] else "a task that includes it"
            found.append(error("ATD212", f"state '{state.name}' includes {what} ('{state.file}')", state.loc,
                               "a task cannot contain itself; loop with transitions instead"))
        else:
            if sub.resolve() not in seen:
                seen[sub.resolve()] = (None, [])
                seen[sub.resolve()] = _load(sub, including, seen)
                found += seen[sub.resolve()][1]
            sub_task = seen[sub.resolve()][0]
            found += _unsimulated_object(task, state, sub_task)
            if sub_task is not None:
                found += _outcomes(task, state, sub_task) + _inputs(task, state, sub_task)
                found += _subtask_roles(task, state, sub_task)
    return found


def _outcomes(task: Task, state: State, sub: Task) -> list[Diagnostic]:
    """An `<outcome name="..."/>` leaving a sub-task state names one of the sub-task's end states."""
    ends = [s.name for s in sub.states if s.type.is_end]
    found = []
    for t in task.transitions:
        if t.origin != state.name:
            continue
        for event in t.events:
            if event.type is EventType.OUTCOME and event.name not in ends:
                found.append(error("ATD224", f"sub-task '{state.file}' of state '{state.name}' has no end state "
                                             f"'{event.name}'", event.loc or t.loc,
                                   f"its outcomes (end states): {', '.join(ends) or 'none'}"))
    return found


def _inputs(task: Task, state: State, sub: Task) -> list[Diagnostic]:
    """A sub-task state gives each of the sub-task's inputs a value of its kind, and no others."""
    declared = {v.name: v.kind for v in sub.inputs}
    kinds = value_kinds(task)
    found = []
    for name in [n for n in declared if n not in state.inputs]:
        found.append(error("ATD225", f"state '{state.name}' gives sub-task '{state.file}' no input '{name}'",
                           state.loc, f'add <input name="{name}" from="..."/>, naming a {declared[name].value} '
                                      "this task writes"))
    for name, source in state.inputs.items():
        if name not in declared:
            found.append(error("ATD225", f"sub-task '{state.file}' of state '{state.name}' has no input '{name}'",
                               state.loc, f"its inputs: {', '.join(declared) or 'none'}"))
        elif source in kinds and kinds[source][0] is not declared[name]:
            kind, by = kinds[source]
            found.append(error("ATD222", f"state '{state.name}' gives input '{name}' (a {declared[name].value}) the "
                                         f"value '{source}', a {kind.value} ({by})", state.loc,
                               f"give it a {declared[name].value}"))
    return found


def _subtask_roles(task: Task, state: State, sub: Task) -> list[Diagnostic]:
    """A sub-task's roles are the including task's, by name; a sub-task that declares none
    runs on the arm of the role its `task` state names."""
    if not sub.roles:
        if state.role is None and len(task.roles) > 1:
            return [error("ATD227", f"state '{state.name}' does not say which role does sub-task '{state.file}', "
                                    "and the task declares several", state.loc,
                          f"add role=\"...\", one of: {', '.join(r.name for r in task.roles)}")]
        return []
    if state.role is not None:
        return [error("ATD103", f"state '{state.name}' gives sub-task '{state.file}' the role '{state.role}', but the "
                                f"sub-task names its own roles ({', '.join(r.name for r in sub.roles)})", state.loc,
                      'remove role="..."; the sub-task\'s roles are bound to this task\'s roles of the same name')]
    declared = {r.name for r in task.roles}
    return [error("ATD226", f"sub-task '{state.file}' of state '{state.name}' needs role '{r.name}', which this task "
                            "does not declare", state.loc, f'add <role name="{r.name}"/> to this task')
            for r in sub.roles if r.name not in declared]


def _unsimulated_object(task: Task, state: State, sub: Task | None) -> list[Diagnostic]:
    """A run simulates the top task's world only; a sub-task describing another object would
    be silently left out of it, so say so."""
    if sub is None or all(o in task.known_objects for o in sub.known_objects):
        return []
    return [warning("ATD217", f"the <object> of sub-task '{state.file}' differs from this task's and is not "
                              "simulated: a run builds the world of the top task only", state.loc,
                    "describe the object in the including task (the same <object> block in both is fine)")]
