"""Graph checks on a task: the mistakes a task author makes that a schema cannot see.

Runs on whatever the reader could read, so one bad state does not hide the rest.
"""

from __future__ import annotations

from collections import defaultdict
from pathlib import Path

from atd.model.diagnostics import Diagnostic, Suggester, did_you_mean, error, has_errors, warning
from atd.model.task import State, Task
from atd.model.vocabulary import StateType


def check_task(task: Task, unreadable_states: frozenset[str] = frozenset(), read_cleanly: bool = True) -> list[Diagnostic]:
    """Every graph-level problem of one task, as diagnostics (sub-tasks not included).

    Reachability is judged only on a graph read without errors: with an edge dropped for
    a typo, "unreachable" warnings would be noise that follows from the typo.
    """
    found: list[Diagnostic] = []
    found += _names(task)
    found += _endpoints(task, unreadable_states)
    found += _ends(task)
    found += _ambiguity(task)
    found += _targets(task)
    found += _shape(task)
    if read_cleanly and not has_errors(found):
        found += _reachability(task)
    return found


def _names(task: Task) -> list[Diagnostic]:
    found = []
    first: dict[str, State] = {}
    for state in task.states:
        if state.name in first:
            line = first[state.name].loc.line if first[state.name].loc else "?"
            found.append(error("ATD201", f"state '{state.name}' is defined twice", state.loc,
                               f"the first definition is at line {line}; rename one of them"))
        else:
            first[state.name] = state
    if task.initial is not None and task.initial not in first:
        found.append(error("ATD213", f"initial state '{task.initial}' does not exist", task.loc,
                           did_you_mean(task.initial, first) or "name one of the task's states"))
    if not task.states:
        found.append(error("ATD204", "the task has no states", task.loc,
                           'add states, ending in one of type="success"'))
    return found


def _endpoints(task: Task, unreadable: frozenset[str]) -> list[Diagnostic]:
    found = []
    names = task.states_by_name
    suggester: Suggester | None = None  # built at the first unknown name, shared by the rest
    for t in task.transitions:
        if t.origin in names and t.destination in names:
            continue
        for end, name in (("origin", t.origin), ("destination", t.destination)):
            if name not in names and name not in unreadable:
                suggester = suggester or Suggester(names)
                found.append(error("ATD202", f"transition {end} '{name}' is not a state", t.loc,
                                   suggester.hint(name) or "name a state defined in this task"))
    return found


def _ends(task: Task) -> list[Diagnostic]:
    found = []
    if task.states and not any(s.type is StateType.SUCCESS for s in task.states):
        found.append(error("ATD204", "no state of type 'success'", task.loc,
                           'add <state name="done" type="success"/> and a transition into it'))
    leaving = {t.origin for t in task.transitions}
    for state in task.states:
        ends_task = state.type.is_end
        if ends_task and state.name in leaving:
            found.append(error("ATD205", f"end state '{state.name}' has outgoing transitions", state.loc,
                               f"a {state.type.value} state ends the task; remove its transitions"))
        elif not ends_task and state.name not in leaving:
            found.append(error("ATD206", f"state '{state.name}' is a dead end: no transition leaves it", state.loc,
                               "add a transition, e.g. on <success/>, to the next state or an end state"))
    return found


def _ambiguity(task: Task) -> list[Diagnostic]:
    """Two edges from one state on the same events cannot both be taken: which one wins?"""
    found = []
    first_on: dict[tuple, int] = {}  # (origin, events): the first transition leaving on them
    for i, t in enumerate(task.transitions):
        j = first_on.setdefault((t.origin, frozenset([(e.type, e.seconds) for e in t.events])), i)
        if j == i:
            continue
        first = task.transitions[j]
        if t.destination != first.destination:
            found.append(error(
                "ATD209",
                f"ambiguous: '{t.origin}' leaves on {t.label} both to '{first.destination}' and to '{t.destination}'",
                t.loc,
                f"the other transition is at line {first.loc.line if first.loc else '?'}; "
                "change one of the event sets or remove one transition",
            ))
        else:
            found.append(warning("ATD214", f"transition {task.transition_ids[i]} repeats "
                                           f"{task.transition_ids[j]}", t.loc, "remove the copy"))
    return found


def _targets(task: Task) -> list[Diagnostic]:
    """Table 7.1 makes a target required for arm primitives; object information can stand in."""
    found = []
    for state in task.states:
        if state.type.moves_arm and not state.path and (task.object is None or task.object.pose is None):
            found.append(warning(
                "ATD210",
                f"{state.type.value} state '{state.name}' has no target and the task gives no object pose",
                state.loc,
                "add <path><position>x y z</position></path>, or an <object> with a <pose> to derive it from",
            ))
    return found


def _shape(task: Task) -> list[Diagnostic]:
    """A mesh named by the object must be there when the task runs, and be one the engines
    can load; say so now."""
    obj = task.object
    if obj is None or obj.shape is None or task.source is None:
        return []
    mesh = Path(task.source).parent / obj.shape
    if mesh.exists():  # a directory or a FIFO too: check_mesh says what it is
        from atd.model.meshcheck import MeshError, check_mesh  # numpy: only for a task that names a mesh

        try:
            check_mesh(mesh)
        except MeshError as exc:
            return [error("ATD216", f"object shape '{obj.shape}': {exc}", obj.loc,
                          "export the mesh again as STL or OBJ, in metres, or remove <shape> to simulate the "
                          "object from its class and size")]
        return []
    return [warning("ATD215", f"object shape '{obj.shape}' not found next to the task", obj.loc,
                    f"looked for {mesh}; simulation needs the mesh there (STL or OBJ), or remove <shape> "
                    "to simulate the object from its class and size")]


def _reachability(task: Task) -> list[Diagnostic]:
    found = []
    after: dict[str, list[str]] = defaultdict(list)
    before: dict[str, list[str]] = defaultdict(list)
    for t in task.transitions:
        after[t.origin].append(t.destination)
        before[t.destination].append(t.origin)
    start = task.initial_state
    reached = _closure({start} if start in task.states_by_name else set(), after)
    finishing = _closure({s.name for s in task.states if s.type.is_end}, before)
    for state in task.states:
        if state.name not in reached:
            found.append(warning("ATD207", f"state '{state.name}' cannot be reached from the initial state '{start}'",
                                 state.loc, "add a transition into it, or remove it"))
        elif state.name not in finishing:
            found.append(warning("ATD208", f"no end state can be reached from state '{state.name}'", state.loc,
                                 "the task would loop forever from here; add a way out, e.g. <timeout>"))
    return found


def _closure(sources: set[str], neighbours: dict[str, list[str]]) -> set[str]:
    """`sources` and every state reached from them along `neighbours`: one search from all at once."""
    found, frontier = set(sources), list(sources)
    while frontier:
        for nxt in neighbours.get(frontier.pop(), ()):
            if nxt not in found:
                found.add(nxt)
                frontier.append(nxt)
    return found


def subtask_path(task: Task, state: State) -> Path:
    """A sub-task's file, relative to the file of the task that includes it."""
    base = Path(task.source).parent if task.source else Path(".")
    return base / (state.file or "")

