"""Graph checks on a task: the mistakes a task author makes that a schema cannot see.

Runs on whatever the reader could read, so one bad state does not hide the rest.
"""

from __future__ import annotations

from pathlib import Path

from atd.model.diagnostics import Diagnostic, Suggester, did_you_mean, error, has_errors, warning
from atd.model.graph import TaskGraph
from atd.model.task import Location, ObjectInfo, State, Task
from atd.model.vocabulary import FINDING_EVENT, FIRED_BY, TARGET_KINDS, TOP_KINDS, StateType, ValueKind

LONGEST_PATH_SHOWN = 6  # states of a path a diagnostic spells out; longer ones elide their middle


def check_task(task: Task, unreadable_states: frozenset[str] = frozenset(), read_cleanly: bool = True) -> list[Diagnostic]:
    """Every graph-level problem of one task, as diagnostics (sub-tasks not included).

    Reachability is judged only on a graph read without errors: with an edge dropped for
    a typo, "unreachable" warnings would be noise that follows from the typo.
    """
    graph = TaskGraph(task)
    found: list[Diagnostic] = []
    found += _names(task)
    found += _endpoints(task, unreadable_states)
    found += _ends(task, graph)
    found += _ambiguity(task)
    found += _objects(task)
    found += _containers(task)
    found += _roles(task)
    found += _events(task)
    found += _kinds(task)
    found += _targets(task)
    found += _shape(task)
    if read_cleanly and not has_errors(found):
        found += _reachability(task, graph)
        found += _data_flow(task, graph)
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


def _ends(task: Task, graph: TaskGraph) -> list[Diagnostic]:
    found = []
    if task.states and not any(s.type is StateType.SUCCESS for s in task.states):
        found.append(error("ATD204", "no state of type 'success'", task.loc,
                           'add <state name="done" type="success"/> and a transition into it'))
    for state in task.states:
        ends_task = state.type.is_end
        leaves = graph.leaving(state.name) > 0
        if ends_task and leaves:
            found.append(error("ATD205", f"end state '{state.name}' has outgoing transitions", state.loc,
                               f"a {state.type.value} state ends the task; remove its transitions"))
        elif not ends_task and not leaves:
            found.append(error("ATD206", f"state '{state.name}' is a dead end: no transition leaves it", state.loc,
                               "add a transition, e.g. on <success/>, to the next state or an end state"))
    return found


def _ambiguity(task: Task) -> list[Diagnostic]:
    """Two edges from one state on the same events cannot both be taken: which one wins?"""
    found = []
    first_on: dict[tuple, int] = {}  # (origin, events): the first transition leaving on them
    for i, t in enumerate(task.transitions):
        j = first_on.setdefault((t.origin, frozenset([e.key for e in t.events])), i)
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


def _objects(task: Task) -> list[Diagnostic]:
    """A task that knows several objects names each, once, and its states say which they act on."""
    found = []
    several = len(task.known_objects) > 1
    first: dict[str, ObjectInfo] = {}
    for obj in task.known_objects:
        if obj.name is None:
            if several:
                found.append(error("ATD102", "<object> has no name, and the task knows several objects", obj.loc,
                                   'add name="..." to each <object> (states say object="name" to act on it)'))
        elif obj.name in first:
            found.append(error("ATD218", f"two objects are called '{obj.name}'", obj.loc,
                               f"the first is at line {_line(first[obj.name].loc)}; rename one of them"))
        else:
            first[obj.name] = obj
    for state in task.states:
        if state.object is not None and state.object not in task.objects:
            found.append(error("ATD219", f"state '{state.name}' acts on object '{state.object}', which the task "
                                         "does not know", state.loc, _known(state.object, first, "object")))
        elif state.object is None and several and _needs_object(state):
            found.append(error("ATD220", f"{state.type.value} state '{state.name}' does not say which object it acts "
                                         "on, and the task knows several", state.loc,
                               f"add object=\"...\", one of: {', '.join(first) or 'the objects, once named'}"))
    return found


def _needs_object(state: State) -> bool:
    """An object primitive, or an arm primitive whose target the object would give."""
    return state.type.acts_on_object or (state.type.moves_arm and not state.path and state.target_from is None)


def _containers(task: Task) -> list[Diagnostic]:
    found = []
    first: dict[str, Location | None] = {}
    for container in task.environment.containers if task.environment else ():
        if container.name in first:
            found.append(error("ATD218", f"two containers are called '{container.name}'", container.loc,
                               f"the first is at line {_line(first[container.name])}; rename one of them"))
        first.setdefault(container.name, container.loc)
    for state in task.states:
        if state.container is not None and state.container not in first:
            found.append(error("ATD219", f"state '{state.name}' looks in container '{state.container}', which the "
                                         "task does not know", state.loc, _known(state.container, first, "container")))
    return found


def _roles(task: Task) -> list[Diagnostic]:
    """Each role a state names is declared, once; with several, every state that uses an arm
    says which; a role no state uses would still ask the robot for an arm."""
    found = []
    first: dict[str, Location | None] = {}
    for role in task.roles:
        if role.name in first:
            found.append(error("ATD218", f"two roles are called '{role.name}'", role.loc,
                               f"the first is at line {_line(first[role.name])}; rename one of them"))
        first.setdefault(role.name, role.loc)
    used: set[str] = set()
    for state in task.states:
        if state.role is not None:
            used.add(state.role)
            if state.role not in first:
                found.append(error("ATD226", f"state '{state.name}' is done by role '{state.role}', which the task "
                                             "does not declare", state.loc, _role_hint(state.role, first)))
        elif len(first) > 1 and not state.type.is_end and state.type is not StateType.TASK:  # a sub-task: load.py
            found.append(error("ATD227", f"{state.type.value} state '{state.name}' does not say which role does it, "
                                         "and the task declares several", state.loc,
                               f"add role=\"...\", one of: {', '.join(first)}"))
    if len(first) == 1 or any(s.type is StateType.TASK and s.role is None for s in task.states):
        used.update(first)  # the only role does every state that names none; a sub-task's own roles are unseen here
    for name, loc in first.items():
        if name not in used:
            found.append(warning("ATD228", f"role '{name}' does nothing: no state names it", loc,
                                 "remove it (each role asks the robot for one more arm), or give it a state"))
    return found


def _role_hint(word: str, declared: dict) -> str:
    if not declared:
        return (f'declare it: <role name="{word}"/> in the <statemachine> (and one <role> per arm the task '
                "needs), or remove role=\"...\" to use the robot's one chosen arm")
    return did_you_mean(word, declared) or (f"the task's roles: {', '.join(declared)}; or declare "
                                            f'<role name="{word}"/>')


def _known(word: str, names: dict, what: str) -> str:
    """A hint naming the closest known name, or all of them, or how to declare one."""
    if not names:
        where = "<environment>" if what == "container" else "<statemachine>"
        return f"the task knows no {what}s; declare one with <{what} name=\"{word}\"> in the {where}"
    return did_you_mean(word, names) or f"the task's {what}s: {', '.join(names)}"


def _line(loc: Location | None) -> str:
    return str(loc.line) if loc else "?"


def _events(task: Task) -> list[Diagnostic]:
    """Perception events leave the primitives that perceive; an outcome leaves a sub-task."""
    found = []
    states = task.states_by_name
    for t in task.transitions:
        origin = states.get(t.origin)
        if origin is None:
            continue
        for event in t.events:
            owners = FIRED_BY.get(event.type)
            if owners is not None and origin.type not in owners:
                kinds = " or ".join(sorted(o.value for o in owners))
                found.append(error("ATD223", f"<{event.type.value}/> leaves '{t.origin}', a {origin.type.value} state; "
                                             f"only a {kinds} state fires it", event.loc or t.loc,
                                   "use an event the state fires, e.g. <success/>, or make the state a "
                                   f"{kinds} state"))
    return found


def value_kinds(task: Task) -> dict[str, tuple[ValueKind, str]]:
    """Each value the task writes or takes as input: its kind, and the first state (or
    `input`) that gives it one."""
    kinds: dict[str, tuple[ValueKind, str]] = {v.name: (v.kind, "the task's <input>") for v in task.inputs}
    for state in task.states:
        for value in state.writes:
            kinds.setdefault(value.name, (value.kind, f"state '{state.name}'"))
    return kinds


def _kinds(task: Task) -> list[Diagnostic]:
    """A value holds one kind, a target is a pose or a point, and a top is read from a pose."""
    found = []
    kinds = value_kinds(task)
    for state in task.states:
        for value in state.writes:
            kind, by = kinds[value.name]
            if kind is not value.kind:
                found.append(error("ATD222", f"state '{state.name}' writes '{value.name}' as a {value.kind.value}, "
                                             f"but {by} gives it as a {kind.value}", value.loc or state.loc,
                                   "a value holds one kind: give this one another name"))
        if state.target_from in kinds and kinds[state.target_from][0] not in TARGET_KINDS:
            kind, by = kinds[state.target_from]
            found.append(error("ATD222", f"state '{state.name}' takes its target from '{state.target_from}', a "
                                         f"{kind.value} ({by}); a target is a pose or a point", state.loc,
                               "read a value a perceive (pose) or explore (point) state writes"))
        if state.top_from in kinds and kinds[state.top_from][0] not in TOP_KINDS:
            kind, by = kinds[state.top_from]
            found.append(error("ATD222", f"state '{state.name}' takes the object's top from '{state.top_from}', "
                                         f"a {kind.value} ({by}); a top is read from a perceive state's approach "
                                         "(a pose)", state.loc, "read the pose a perceive state writes"))
    return found


def _targets(task: Task) -> list[Diagnostic]:
    """Table 7.1 makes a target required for arm primitives; object information can stand in."""
    found = []
    for state in task.states:
        obj = task.objects.get(state.object) if state.object else task.object
        if state.type.moves_arm and not state.path and not state.target_from and (obj is None or obj.pose is None):
            found.append(warning(
                "ATD210",
                f"{state.type.value} state '{state.name}' has no target and the task gives no object pose",
                state.loc,
                "add <path><position>x y z</position></path>, or an <object> with a <pose> to derive it from",
            ))
    return found


def _shape(task: Task) -> list[Diagnostic]:
    """A mesh named by an object must be there when the task runs, and be one the engines
    can load; say so now."""
    return [d for obj in task.known_objects for d in _object_shape(task, obj)]


def _object_shape(task: Task, obj: ObjectInfo) -> list[Diagnostic]:
    if obj.shape is None or task.source is None:
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


def _reachability(task: Task, graph: TaskGraph) -> list[Diagnostic]:
    found = []
    start = task.initial_state
    reached, finishing = graph.reached, graph.finishing
    for state in task.states:
        if state.name not in reached:
            found.append(warning("ATD207", f"state '{state.name}' cannot be reached from the initial state '{start}'",
                                 state.loc, "add a transition into it, or remove it"))
        elif state.name not in finishing:
            found.append(warning("ATD208", f"no end state can be reached from state '{state.name}'", state.loc,
                                 "the task would loop forever from here; add a way out, e.g. <timeout>"))
    return found


def _data_flow(task: Task, graph: TaskGraph) -> list[Diagnostic]:
    """A state reads only values written on every way to it from the initial state."""
    readers = [s for s in task.states if s.reads]
    if not readers:
        return []
    found = []
    available = graph.available
    writers: dict[str, list[State]] = {}
    for state in task.states:
        for value in state.writes:
            writers.setdefault(value.name, []).append(state)
    for state in readers:
        if state.name not in available:
            continue  # unreachable: ATD207 says so
        for name in state.reads:
            if name in available[state.name]:
                continue
            path = graph.unwritten_path(name, state.name)
            found.append(error("ATD221", f"state '{state.name}' reads '{name}', which is not written on every way to "
                                         f"it: {_spelt(path)} writes it nowhere", state.loc,
                               _writer_hint(name, state, writers.get(name, []), task)))
    return found


def _spelt(path: list[str]) -> str:
    if len(path) > LONGEST_PATH_SHOWN:
        path = path[:2] + ["..."] + path[-(LONGEST_PATH_SHOWN - 3):]
    return " -> ".join(path)


def _writer_hint(name: str, reader: State, writers: list[State], task: Task) -> str:
    """Which states could write the value, and on which event; or that none does."""
    if not writers:
        close = did_you_mean(name, value_kinds(task))
        return close or (f"no state writes '{name}': add <writes name=\"{name}\" kind=\"...\"/> to a perceive or "
                         f"explore state on every way to '{reader.name}', or <input name=\"{name}\" kind=\"...\"/> "
                         "to a sub-task")
    said = ", ".join(f"'{w.name}' writes it when it leaves on <{FINDING_EVENT[w.type].value}/>"
                     for w in writers[:3] if w.type in FINDING_EVENT)
    return f"{said}; make every way into '{reader.name}' pass through such a transition"


def subtask_path(task: Task, state: State) -> Path:
    """A sub-task's file, relative to the file of the task that includes it."""
    base = Path(task.source).parent if task.source else Path(".")
    return base / (state.file or "")

