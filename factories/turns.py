"""Which way the hand points as a state begins, as the task believes it: the turn the last
`<pose>` before it gave the hand, carried through the states that keep the hand's
orientation (a grasp approaches along it, a transport lifts with it, docs/atd-format.md)."""

from __future__ import annotations

import numpy as np

from atd.model.task import State, Task
from atd.model.vocabulary import StateType

# States whose arm keeps the orientation the hand arrived with.
KEEPING = frozenset({StateType.GRASP, StateType.TRANSPORT, StateType.PLACE, StateType.RELEASE})
ENDS = frozenset({StateType.SUCCESS, StateType.FAILURE})


def target_turn(state: State) -> np.ndarray | None:
    """The rotation of a path's last waypoint when it is a `<pose>`: the hand's turn away from
    pointing straight down (with the yaw it has) at the target, in the world frame."""
    target = state.path[-1] if state.path else None
    if target is None or target.kind != "pose":
        return None
    v = target.values
    return np.array([v[0:3], v[4:7], v[8:11]], float)


def arriving(task: Task, state: State) -> State | None:
    """The state the hand comes from into `state`: the origin of the first transition into it
    (document order) that is not an end state; None for the initial state or a sub-task's."""
    for transition in task.transitions:
        origin = task.states_by_name.get(transition.origin)
        if transition.destination == state.name and origin is not None and origin.type not in ENDS:
            return origin
    return None


def turn_at_start(task: Task, state: State) -> np.ndarray | None:
    """The hand's turn as `state` begins (None: pointing down), followed back through the
    states that keep it; another role's states in between move another arm, which leaves
    this one's hand as it was (the two-arm task's holder keeps its side turn while the
    opener works)."""
    seen = {state.name}
    role = task.role_of(state)
    before = arriving(task, state)
    while before is not None and before.name not in seen:
        seen.add(before.name)
        if task.role_of(before) == role:
            turn = target_turn(before)
            if turn is not None or before.type not in KEEPING:
                return turn
        before = arriving(task, before)
    return None


def grasp_ahead(task: Task, state: State) -> State | None:
    """The grasp a move leads to: the first grasp state reached from `state` through moves
    only (transitions in document order), the one the hand comes down for; None if none."""
    seen = {state.name}
    frontier = [state]
    while frontier:
        here = frontier.pop(0)
        for _, transition in task.outgoing(here.name):
            after = task.states_by_name.get(transition.destination)
            if after is None or after.name in seen:
                continue
            if after.type is StateType.GRASP:
                return after
            seen.add(after.name)
            if after.type is StateType.MOVE:
                frontier.append(after)
    return None


def leads_into(task: Task, state: State, kind: StateType) -> State | None:
    """The first state of type `kind` (document order) an edge from `state` goes straight
    to: the unscrew a move ends where it pinches; None if none."""
    for _, transition in task.outgoing(state.name):
        after = task.states_by_name.get(transition.destination)
        if after is not None and after.type is kind:
            return after
    return None
