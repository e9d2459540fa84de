"""The Embodiment Specific Task Description as data: the executable state machine.

It mirrors the ATD it came from: one state per ATD state, one transition per ATD
transition, one event per abstract event of that transition. Each event holds a tree
of concrete conditions (`all`/`any` of leaves from `atd.model.controllers`), and every
element carries `atd`, the id of the ATD element it came from, so a run can report in
the task's own terms. `validate_vocabulary` checks names and parameters against the
vocabulary, because an ESTD is also read back from files written elsewhere.
"""

from __future__ import annotations

from functools import cached_property
from pathlib import Path

from typing import Annotated, Literal, Union

from atd.model.frozen import Frozen
from pydantic import Discriminator, Field, Tag

from atd.model.controllers import (
    ARM_CONTROLLERS,
    CONDITIONS,
    HAND_CONTROLLERS,
    ParamValue,
    check_params,
    format_value,
)
from atd.model.task import Environment, KnowsObjects, Value
from atd.model.vocabulary import EventType, StateType

FORMAT_VERSION = 1


class EstdElement(Frozen):
    """Base of every ESTD element."""


class Controller(EstdElement):
    """A concrete primitive controller and its parameters."""

    name: str
    params: dict[str, ParamValue] = Field(default_factory=dict)


class Condition(EstdElement):
    """A leaf: one sensor test or controller status, with its thresholds."""

    kind: str
    sensors: tuple[str, ...] = ()
    params: dict[str, ParamValue] = Field(default_factory=dict)
    atd: str = ""  # the ATD event it helps detect: `<transition id>/<event type>`


class ConditionGroup(EstdElement):
    """`all` (AND) or `any` (OR) of its children."""

    op: Literal["all", "any"]
    children: tuple[ConditionNode, ...] = Field(min_length=1)


def _node_tag(value: object) -> str:
    if isinstance(value, dict):
        return "group" if "op" in value else "leaf"
    return "group" if isinstance(value, ConditionGroup) else "leaf"


ConditionNode = Annotated[
    Union[Annotated[Condition, Tag("leaf")], Annotated[ConditionGroup, Tag("group")]],
    Discriminator(_node_tag),
]
ConditionGroup.model_rebuild()


def leaves(node: Condition | ConditionGroup) -> list[Condition]:
    """Every leaf condition under a node, left to right."""
    if isinstance(node, Condition):
        return [node]
    return [leaf for child in node.children for leaf in leaves(child)]


class EstdEvent(EstdElement):
    """One abstract event of an ATD transition, as the robot detects it."""

    type: EventType
    atd: str
    condition: ConditionNode


class EstdState(EstdElement):
    """One ATD state: the concrete primitive that runs it, or a sub-machine, or an end."""

    name: str
    type: StateType
    atd: str
    loc: str | None = None  # `file:line` of the ATD state
    primitive: str | None = None  # the robot's name for the primitive (Tables 7.3, 7.4)
    arm: Controller | None = None
    hand: Controller | None = None
    machine: Estd | None = None  # a translated sub-task
    # What the ATD state says of the data around it, for the runtime (docs/atd-format.md):
    object: str | None = None  # which of the task's objects it acts on
    writes: tuple[Value, ...] = ()  # the values it writes when it leaves on its finding event
    target_from: str | None = None  # the value its target is read from when it starts
    target_offset: tuple[float, float, float] | None = None  # m, world frame, added to that value's position
    top_from: str | None = None  # a grasp: the value whose seen top its arm controller takes as the object's
    inputs: dict[str, str] = Field(default_factory=dict)  # sub-task input -> this machine's value
    role: str | None = None  # the ATD role doing it, in a task that names roles
    robot_arm: str | None = None  # the robot's arm that runs it, where the task names roles; None: `Estd.arm`


class EstdTransition(EstdElement):
    """One ATD transition: taken when all its events hold."""

    origin: str
    destination: str
    atd: str  # `Task.transition_ids` of the ATD edge
    loc: str | None = None
    events: tuple[EstdEvent, ...] = Field(min_length=1)


class Estd(EstdElement, KnowsObjects):
    """A whole ESTD: the machine for one robot (and arm) translated from one ATD file."""

    robot: str
    arm: str
    source: str | None = None  # the ATD file; relative object shapes are relative to it
    initial: str
    environment: Environment | None = None
    inputs: tuple[Value, ...] = ()  # a sub-machine's values its parent gives it
    roles: dict[str, str] = Field(default_factory=dict)  # the task's roles -> the robot's arms bound to them
    states: tuple[EstdState, ...]
    transitions: tuple[EstdTransition, ...] = ()
    version: int = FORMAT_VERSION

    @cached_property
    def states_by_name(self) -> dict[str, EstdState]:
        return {s.name: s for s in self.states}

    @cached_property
    def leaving(self) -> dict[str, tuple[EstdTransition, ...]]:
        """Each state's outgoing transitions in document order: what the executor checks
        each tick, found without scanning the whole machine."""
        out: dict[str, list[EstdTransition]] = {}
        for t in self.transitions:
            out.setdefault(t.origin, []).append(t)
        return {origin: tuple(ts) for origin, ts in out.items()}

    @cached_property
    def arms(self) -> tuple[str, ...]:
        """Every arm of the robot some state of this machine or its sub-machines runs on, the
        ESTD's own first: the arms a run must simulate."""
        used = [self.arm] + [s.robot_arm for _, m in self.walk() for s in m.states if s.robot_arm]
        return tuple(dict.fromkeys(used))

    @property
    def arm_text(self) -> str:
        """Which arm does the work, for people: `right arm`, or each role's, `holder on right, worker on left`."""
        if not self.roles:
            return f"{self.arm} arm"
        return ", ".join(f"{role} on {arm}" for role, arm in self.roles.items())

    def files(self) -> list[Path]:
        """Every file this ESTD was made from (each machine's ATD, the object's mesh): the
        files a command that writes must never overwrite."""
        found = [Path(machine.source) for _, machine in self.walk() if machine.source]
        if self.source:
            found += [Path(self.source).parent / o.shape for o in self.known_objects if o.shape]
        return found

    def walk(self, prefix: str = "") -> list[tuple[str, Estd]]:
        """This machine and every nested sub-machine, each with its state path."""
        found = [(prefix, self)]
        for state in self.states:
            if state.machine is not None:
                found += state.machine.walk(f"{prefix}{state.name}/")
        return found


EstdState.model_rebuild()


def validate_vocabulary(estd: Estd) -> list[str]:
    """Every use of a controller or condition that the vocabulary does not allow."""
    problems: list[str] = []
    for prefix, machine in estd.walk():
        for state in machine.states:
            where = f"state '{prefix}{state.name}'"
            for role, known, controller in (("arm", ARM_CONTROLLERS, state.arm), ("hand", HAND_CONTROLLERS, state.hand)):
                if controller is None:
                    continue
                spec = known.get(controller.name)
                if spec is None:
                    problems.append(f"{where}: unknown {role} controller '{controller.name}'")
                else:
                    supplied = frozenset({"target"} if role == "arm" and state.target_from else ())
                    problems += check_params(f"{where} {role} '{controller.name}'", spec.params, controller.params,
                                             supplied)
        for transition in machine.transitions:
            for event in transition.events:
                for leaf in leaves(event.condition):
                    where = f"transition '{prefix}{transition.atd}' event '{event.type.value}'"
                    spec = CONDITIONS.get(leaf.kind)
                    if spec is None:
                        problems.append(f"{where}: unknown condition '{leaf.kind}'")
                        continue
                    problems += check_params(f"{where} condition '{leaf.kind}'", spec.params, leaf.params)
                    if (spec.reads is None) != (not leaf.sensors):
                        need = f"names sensors of kind {spec.reads.value}" if spec.reads else "reads no sensor"
                        problems.append(f"{where}: condition '{leaf.kind}' {need}")
    return problems


def describe(node: Condition | ConditionGroup, thresholds: bool = False) -> str:
    """One line for people: `all(arm_done, hand_done)`; with thresholds, leaves show their parameters."""
    if isinstance(node, ConditionGroup):
        return f"{node.op}({', '.join(describe(c, thresholds) for c in node.children)})"
    if not thresholds or not (node.params or node.sensors):
        return node.kind
    params = [f"{k}={format_value(v)}" for k, v in sorted(node.params.items())]
    sensors = [f"on={'+'.join(node.sensors)}"] if node.sensors else []
    return f"{node.kind}[{', '.join(sensors + params)}]"
