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
from atd.model.validate import check_task, subtask_path
from atd.model.vocabulary import StateType
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
            found += _unsimulated_object(task, state, seen[sub.resolve()][0])
    return found


def _unsimulated_object(task: Task, state: State, sub: Task | None) -> list[Diagnostic]:
    """A run simulates the top task's world only; a sub-task describing another object would
    be silently left out of it, so say so."""
    if sub is None or sub.object is None or sub.object == task.object:
        return []
    return [warning("ATD217", f"the <object> of sub-task '{state.file}' differs from this task's and is not "
                              "simulated: a run builds the world of the top task only", state.loc,
                    "describe the object in the including task (the same <object> block in both is fine)")]
