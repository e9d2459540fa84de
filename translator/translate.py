"""Translation: every node through the factory first, then every edge (thesis 7.2.2).

Each unmappable node or edge gives one diagnostic with the ATD file:line, the robot and
the factory's reason, and translation goes on so the author sees all of them at once;
but then no ESTD is returned. A result that breaks the three rules or the vocabulary is
the factory's fault and is refused the same way.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Mapping

from atd.model.bulk import cyclic_gc_paused
from atd.model.controllers import CONDITIONS, CONTROLLERS, parse_value
from atd.model.diagnostics import Diagnostic, Severity, error, has_errors, warning
from atd.model.estd import (
    Condition,
    ConditionGroup,
    Controller,
    Estd,
    EstdEvent,
    EstdState,
    EstdTransition,
    leaves,
    validate_vocabulary,
)
from atd.model.load import load_task
from atd.model.task import Environment, Location, State, Task, Transition
from atd.model.validate import subtask_path
from atd.model.vocabulary import EventType, StateType
from factories.base import Factory, MappingContext, NodeMapping, Unmappable
from translator.roles import bind_roles
from translator.rules import check_rules, event_ids

Loader = Callable[[Path], tuple[Task | None, list[Diagnostic]]]


@dataclass
class Translation:
    estd: Estd | None
    diagnostics: list[Diagnostic] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return self.estd is not None


def translate(task: Task, factory: Factory, load: Loader = load_task,
              roles: Mapping[str, str] | None = None) -> Translation:
    """Translate `task` for the factory's robot; `load` reads sub-task files (default: load_task);
    `roles` binds some of the task's roles to arms by name (the rest: translator.roles)."""
    binding, problems = bind_roles(task, factory, roles)
    if problems:
        return Translation(None, problems)
    translator = _Translator(factory, load)
    source = Path(task.source).resolve() if task.source else None
    with cyclic_gc_paused():
        estd = translator.machine(task, (source,) if source else (), binding)
    if estd is None or has_errors(translator.diagnostics):
        return Translation(None, translator.diagnostics)
    return Translation(estd, translator.diagnostics)


def _loc_text(loc: Location | None) -> str | None:
    return f"{loc.file}:{loc.line}" if loc and loc.line else (loc.file if loc else None)


def _stamped(node: Condition | ConditionGroup, atd: str) -> Condition | ConditionGroup:
    """The same tree with every leaf carrying `atd` (already validated, so not validated again)."""
    if isinstance(node, Condition):
        return Condition.model_construct(kind=node.kind, sensors=node.sensors, params=node.params, atd=atd)
    return ConditionGroup.model_construct(op=node.op, children=tuple(_stamped(c, atd) for c in node.children))


Binding = Mapping[str | None, Factory]  # a machine's roles (None: its only, unnamed one) -> the factory on its arm


def _label(factory: Factory) -> str:
    """The robot, and the arm where it has several: how diagnostics name who cannot do it."""
    return factory.name if len(factory.arms) == 1 else f"{factory.name} ({factory.arm.name} arm)"


class _Translator:
    def __init__(self, factory: Factory, load: Loader) -> None:
        self.factory = factory
        self.load = load
        self.diagnostics: list[Diagnostic] = []

    def _refuse(self, factory: Factory, code: str, what: str, reason: str, loc: Location | None,
                hint: str | None) -> None:
        self.diagnostics.append(error(code, f"{_label(factory)}: cannot map {what}: {reason}", loc, hint))

    # -- a whole machine ----------------------------------------------------------------
    def machine(self, task: Task, chain: tuple[Path, ...], binding: Binding,
                surroundings: Environment | None = None) -> Estd | None:
        context = MappingContext(task, surroundings)
        failures_before = self._errors()
        states = [self.node(state, task, context, chain, binding) for state in task.states]
        transitions = [self.edge(tid, t, context, binding[task.role_of(context.state(t.origin))])
                       for tid, t in zip(task.transition_ids, task.transitions)]
        if self._errors() > failures_before:
            return None
        named = {role: f.arm.name for role, f in binding.items() if role is not None}
        estd = Estd(robot=self.factory.name, arm=self.factory.arm.name, source=task.source,
                    initial=task.initial_state or "", known_objects=task.known_objects, environment=task.environment,
                    inputs=task.inputs, roles=named, states=tuple(states), transitions=tuple(transitions))
        problems = check_rules(task, estd) + self._sensor_problems(estd) + validate_vocabulary(estd)
        for problem in problems:
            self.diagnostics.append(error("TRN100", f"{_label(self.factory)}: refusing to emit an ESTD: {problem}", task.loc,
                                          f"this is a defect in the '{self.factory.name}' factory; report it"))
        return None if problems else estd

    def _errors(self) -> int:
        return sum(d.severity is Severity.ERROR for d in self.diagnostics)

    def _sensor_problems(self, estd: Estd) -> list[str]:
        problems = []
        arms = {a.name: {s.name: s.kind for s in a.sensors} for a in self.factory.arms}
        for edge in estd.transitions:
            origin = estd.states_by_name.get(edge.origin)
            sensors = arms[origin.robot_arm if origin and origin.robot_arm else estd.arm]
            for event in edge.events:
                for leaf in leaves(event.condition):
                    reads = CONDITIONS[leaf.kind].reads if leaf.kind in CONDITIONS else None
                    for sensor in leaf.sensors:
                        if sensors.get(sensor) != reads:
                            problems.append(f"condition '{leaf.kind}' of '{event.atd}' reads '{sensor}', which is "
                                            f"not a {reads.value if reads else 'sensor it reads'} sensor of the robot")
        return problems

    # -- nodes --------------------------------------------------------------------------
    def node(self, state: State, task: Task, context: MappingContext, chain: tuple[Path, ...],
             binding: Binding) -> EstdState | None:
        base = {"name": state.name, "type": state.type, "atd": state.name, "loc": _loc_text(state.loc),
                "object": state.object, "writes": state.writes, "target_from": state.target_from,
                "target_offset": state.target_offset, "top_from": state.top_from, "inputs": state.inputs}
        if state.type.is_end:
            return EstdState(**base)
        role = task.role_of(state)
        factory = binding[role]
        if role is not None or factory.arm is not self.factory.arm:
            base.update(role=role, robot_arm=factory.arm.name)
        if state.type is StateType.TASK:
            machine = self.subtask(state, context, chain, binding)
            return EstdState(**base, machine=machine) if machine else None
        try:
            mapping = factory.map_state(state, context.acting_on(state.object))
        except Unmappable as exc:
            self._refuse(factory, "TRN001", f"{state.type.value} state '{state.name}'", exc.reason, state.loc, exc.hint)
            return None
        for note in mapping.notes:
            self.diagnostics.append(warning("TRN010", f"{_label(factory)}: state '{state.name}': {note}", state.loc))
        arm, hand = self.overridden(factory, state, mapping)
        return EstdState(**base, primitive=mapping.primitive, arm=arm, hand=hand)

    def overridden(self, factory: Factory, state: State, mapping: NodeMapping) -> tuple[Controller, Controller]:
        """The ATD's <parameter> overrides applied to whichever controller takes that parameter.

        Thesis 7.2: optional parameters are hints, so one the robot does not use is
        ignored with a warning; a value of the wrong type is an error.
        """
        controllers = {"arm": mapping.arm, "hand": mapping.hand}
        for name, text in sorted(state.parameters.items()):
            users = [role for role, c in controllers.items()
                     if c.name in CONTROLLERS and name in CONTROLLERS[c.name].params
                     and CONTROLLERS[c.name].params[name].tunable]
            if not users:
                self.diagnostics.append(warning(
                    "TRN011", f"{_label(factory)}: state '{state.name}': parameter '{name}' is not a tunable parameter of "
                    f"'{mapping.arm.name}' or '{mapping.hand.name}'; ignored", state.loc,
                    "see `atd robots show` and docs/estd.md for the parameters each controller takes"))
            for role in users:
                controller = controllers[role]
                try:
                    value = parse_value(CONTROLLERS[controller.name].params[name], text)
                except ValueError as exc:
                    self._refuse(factory, "TRN004", f"parameter '{name}' of state '{state.name}'", str(exc), state.loc,
                                 f"give a value of the type '{controller.name}' expects")
                    continue
                controllers[role] = controller.model_copy(update={"params": {**controller.params, name: value}})
        return controllers["arm"], controllers["hand"]

    def subtask(self, state: State, context: MappingContext, chain: tuple[Path, ...], binding: Binding) -> Estd | None:
        path = subtask_path(context.task, state)
        factory = binding[context.task.role_of(state)]
        if path.resolve() in chain:
            self._refuse(factory, "TRN003", f"task state '{state.name}'", f"'{state.file}' includes itself", state.loc,
                         "a task cannot contain itself; loop with transitions instead")
            return None
        sub, found = self.load(path)
        if sub is None or has_errors(found):
            self.diagnostics.extend(d for d in found if d.severity is Severity.ERROR)
            self._refuse(factory, "TRN003", f"task state '{state.name}'", f"sub-task '{state.file}' is not a valid ATD",
                         state.loc, f"run: atd validate {path}")
            return None
        # Its roles are this task's of the same name (validation checked they are declared);
        # a sub-task that names none runs on the arm of the role its state names.
        inner = {r.name: binding[r.name] for r in sub.roles} if sub.roles else {None: factory}
        return self.machine(sub, chain + (path.resolve(),), inner, context.environment)

    # -- edges --------------------------------------------------------------------------
    def edge(self, tid: str, transition: Transition, context: MappingContext,
             factory: Factory) -> EstdTransition | None:
        origin = context.state(transition.origin)
        ids = event_ids(tid, [e.type.value for e in transition.events])
        events = []
        for atd, event in zip(ids, transition.events):
            try:
                if origin.type is StateType.TASK and event.type is EventType.OUTCOME:
                    node: Condition | ConditionGroup = Condition(kind="subtask_ended_in",
                                                                 params={"end_state": event.name})
                elif origin.type is StateType.TASK and event.type in _SUBTASK_OUTCOMES:
                    node = Condition(kind=_SUBTASK_OUTCOMES[event.type])
                else:
                    node = factory.map_event(event.type, event.seconds, transition,
                                                  context.acting_on(origin.object))
            except Unmappable as exc:
                self._refuse(factory, "TRN002", f"event '{event.type.value}' of transition {tid}", exc.reason,
                             event.loc or transition.loc, exc.hint)
                continue
            events.append(EstdEvent(type=event.type, atd=atd, condition=_stamped(node, atd)))
        if len(events) != len(transition.events):
            return None
        return EstdTransition(origin=transition.origin, destination=transition.destination, atd=tid,
                              loc=_loc_text(transition.loc), events=tuple(events))


# A sub-task reports how its machine ended; every other event on its edges is sensed as usual.
_SUBTASK_OUTCOMES = {EventType.SUCCESS: "subtask_succeeded", EventType.ERROR: "subtask_failed"}
