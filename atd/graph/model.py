"""What a task drawing shows, whatever draws it: boxes with lines of text, labelled arrows.

An ATD and an ESTD become the same kind of `Graph`, so the DOT writer and the library
layout never need to know which language they are drawing.
"""

from __future__ import annotations

import textwrap
from dataclasses import dataclass, field
from enum import StrEnum
from pathlib import Path

from atd.model.controllers import format_number, format_value
from atd.model.estd import Condition, Controller, Estd, EstdEvent, EstdState, describe
from atd.model.task import State, Task
from atd.model.vocabulary import StateType

# The controller parameters worth a line in a box; the rest are tuning (shown with all_params).
WRAP_WIDTH = 44  # characters per label line when conditions are shown
KEY_PARAMS = ("target", "shape", "preshape", "grasp_shape", "grasp_force", "hand_position")


class NodeKind(StrEnum):
    """How a box is drawn: renderers pick colours and borders from this."""

    PRIMITIVE = "primitive"
    SUBTASK = "subtask"
    SUCCESS = "success"
    FAILURE = "failure"


class Trail(StrEnum):
    """How a box or arrow stands to a run drawn on the graph (atd/graph/trail.py)."""

    PLAIN = "plain"  # no run is drawn: the task alone
    TAKEN = "taken"  # the run visited the state, or took the transition
    FADED = "faded"  # the run never went there: drawn grey


@dataclass(frozen=True)
class Node:
    id: str
    lines: tuple[str, ...]  # the first line is the state's name
    kind: NodeKind
    initial: bool = False
    trail: Trail = Trail.PLAIN


@dataclass(frozen=True)
class Edge:
    source: str
    target: str
    lines: tuple[str, ...]
    id: str  # the ATD transition id, so a drawing can be matched to diagnostics
    trail: Trail = Trail.PLAIN


@dataclass
class Graph:
    title: str
    nodes: list[Node] = field(default_factory=list)
    edges: list[Edge] = field(default_factory=list)


def _kind(state_type: StateType) -> NodeKind:
    if state_type is StateType.SUCCESS:
        return NodeKind.SUCCESS
    if state_type is StateType.FAILURE:
        return NodeKind.FAILURE
    return NodeKind.SUBTASK if state_type is StateType.TASK else NodeKind.PRIMITIVE


def _point(values: tuple[float, ...]) -> str:
    return " ".join(format_number(round(v, 4)) for v in values)


def _atd_lines(state: State) -> list[str]:
    """Type and the parameters that tell states apart: where to, with which hand shape."""
    head = state.type.value + (f", {state.movement.value}" if state.movement else "")
    lines = [state.name, head]
    if state.role is not None:
        lines.append(f"role: {state.role}")
    if state.type is StateType.TASK:
        lines.append(f"file: {state.file}")
    if state.preshape:
        lines.append(f"preshape: {state.preshape.value}")
    if state.hand_shape:
        lines.append(f"hand: {state.hand_shape.value}")
    if state.object_size is not None:
        lines.append(f"object size: {format_number(state.object_size)} m")
    if state.hand_opening is not None:
        lines.append(f"opening: {format_number(state.hand_opening)}")
    if state.target is not None:
        via = len(state.path) - 1
        lines.append(f"to: {_point(state.target.position)}" + (f" (via {via})" if via else ""))
    lines += [f"{name}={value}" for name, value in sorted(state.parameters.items())]
    return lines


def from_task(task: Task, file: str) -> Graph:
    """One box per ATD state, one arrow per transition labelled with its abstract events."""
    initial = task.initial_state
    graph = Graph(title=f"{Path(file).name}  (ATD, initial state: {initial})")
    for state in task.states:
        graph.nodes.append(Node(state.name, tuple(_atd_lines(state)), _kind(state.type), state.name == initial))
    for tid, transition in zip(task.transition_ids, task.transitions):
        graph.edges.append(Edge(transition.origin, transition.destination, (transition.label,), tid))
    return graph


def _controller_lines(role: str, controller: Controller, all_params: bool) -> list[str]:
    names = sorted(controller.params) if all_params else [k for k in KEY_PARAMS if k in controller.params]
    return [f"{role}: {controller.name}"] + [f"  {k}={format_value(controller.params[k])}" for k in names]


def _estd_lines(state: EstdState, all_params: bool) -> list[str]:
    lines = [state.name]
    if state.machine is not None:
        source = Path(state.machine.source).name if state.machine.source else "sub-task"
        return lines + ["task", f"file: {source}", f"{len(state.machine.states)} states"]
    if state.primitive is None or state.primitive == state.type.value:
        lines.append(state.type.value)
    else:
        lines.append(f"{state.type.value} as {state.primitive}")
    if state.robot_arm is not None:
        who = f"{state.role} " if state.role else ""
        lines.append(f"{who}on the {state.robot_arm} arm")
    for role, controller in (("arm", state.arm), ("hand", state.hand)):
        if controller is not None:
            lines += _controller_lines(role, controller, all_params)
    return lines


def _wrap(text: str) -> list[str]:
    """Long condition trees broken after their commas, so a label stays a column, not a banner."""
    return textwrap.wrap(text, WRAP_WIDTH, subsequent_indent="    ", break_long_words=False,
                         break_on_hyphens=False)


def _event_word(event: EstdEvent) -> str:
    """The event as the ATD wrote it: a timeout shows its time limit, like `Transition.label`."""
    condition = event.condition
    if isinstance(condition, Condition) and condition.kind == "timeout" and "seconds" in condition.params:
        return f"timeout({format_value(condition.params['seconds'])}s)"
    return event.type.value


def from_estd(estd: Estd, file: str, conditions: bool = False, all_params: bool = False) -> Graph:
    """One box per ESTD state with its primitive and controllers, one arrow per transition.

    Arrows carry the abstract events; with `conditions`, each event also shows the concrete
    condition tree (with thresholds) the robot checks for it.
    """
    graph = Graph(title=f"{Path(file).name}  (ESTD for {estd.robot}, {estd.arm_text}, initial state: {estd.initial})")
    for state in estd.states:
        graph.nodes.append(Node(state.name, tuple(_estd_lines(state, all_params)), _kind(state.type),
                                state.name == estd.initial))
    for transition in estd.transitions:
        if conditions:
            lines = tuple(line for e in transition.events
                          for line in _wrap(f"{e.type.value}: {describe(e.condition, thresholds=True)}"))
        else:
            lines = (" & ".join(_event_word(e) for e in transition.events),)
        graph.edges.append(Edge(transition.origin, transition.destination, lines, transition.atd))
    return graph
