"""Hypothesis strategies for valid ATD tasks, shared by model and translator tests."""

from __future__ import annotations

import numpy as np
from hypothesis import strategies as st

from atd.model import (
    Environment,
    Event,
    EventType,
    HandShape,
    Movement,
    ObjectClass,
    ObjectInfo,
    Obstacle,
    Pose,
    Role,
    State,
    StateType,
    Task,
    Transition,
    Waypoint,
)
from atd.model.vocabulary import FIRED_BY, SIZE_LAYOUT

coordinate = st.floats(-1.0, 1.0, allow_nan=False, allow_infinity=False)
positive = st.floats(1e-3, 10.0, allow_nan=False, allow_infinity=False)
names = st.from_regex(r"[a-z][a-z0-9_]{0,11}", fullmatch=True)


@st.composite
def poses(draw) -> Pose:
    """A random rotation (from a unit quaternion) and translation."""
    q = np.array(draw(st.tuples(*[st.floats(-1, 1, allow_nan=False)] * 4)))
    if np.linalg.norm(q) < 1e-3:
        q = np.array([1.0, 0, 0, 0])
    w, x, y, z = q / np.linalg.norm(q)
    rotation = np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])
    m = np.eye(4)
    m[:3, :3] = rotation
    m[:3, 3] = draw(st.tuples(coordinate, coordinate, coordinate))
    return Pose(matrix=tuple(float(v) for v in m.ravel()))


waypoints = st.one_of(
    st.builds(lambda v: Waypoint(kind="position", values=v), st.tuples(coordinate, coordinate, coordinate)),
    st.builds(lambda v: Waypoint(kind="point", values=v), st.tuples(coordinate, coordinate, coordinate)),
    st.builds(lambda p: Waypoint(kind="pose", values=p.matrix), poses()),
)


@st.composite
def objects(draw) -> ObjectInfo:
    kind = draw(st.none() | st.sampled_from(ObjectClass))
    size = draw(st.none() | st.tuples(*[positive] * len(SIZE_LAYOUT[kind or ObjectClass.BOX])))
    return ObjectInfo(
        pose=draw(st.none() | poses()),
        weight=draw(st.none() | positive),
        inertia=draw(st.none() | st.tuples(*[coordinate] * 9)),
        shape=draw(st.none() | st.just("mug.stl")),
        friction=draw(st.none() | st.floats(0, 2)),
        object_class=kind,
        size=size,
    )


ARM = [StateType.MOVE, StateType.TRANSPORT, StateType.PLACE, StateType.PUSH]
HAND = [StateType.GRASP, StateType.RELEASE]


@st.composite
def primitive_states(draw, name: str, arm_types=tuple(ARM), hand_types=tuple(HAND)) -> State:
    kind = draw(st.sampled_from(list(arm_types) + list(hand_types)))
    return State(
        name=name,
        type=kind,
        movement=draw(st.none() | st.sampled_from(Movement)),
        hand_shape=draw(st.none() | st.sampled_from(HandShape)),
        path=tuple(draw(st.lists(waypoints, min_size=1, max_size=3))) if kind.moves_arm else (),
        preshape=draw(st.none() | st.sampled_from(HandShape)) if kind is StateType.GRASP else None,
        object_size=draw(st.none() | positive) if kind is StateType.GRASP else None,
        hand_opening=draw(st.none() | st.floats(0, 1)) if kind is StateType.RELEASE else None,
        parameters=draw(st.dictionaries(st.sampled_from(["force_threshold", "velocity"]),
                                        st.sampled_from(["0.5", "0.005", "1"]), max_size=2)),
    )


events = st.one_of(
    # Events any primitive fires: the perception events and outcomes leave only their own states.
    st.builds(lambda t: Event(type=t), st.sampled_from([e for e in EventType
                                                        if e is not EventType.TIMEOUT and e not in FIRED_BY])),
    st.builds(lambda s: Event(type=EventType.TIMEOUT, seconds=s), positive),
)


@st.composite
def tasks(draw, max_states: int = 8, **state_kinds) -> Task:
    """A valid task: a chain of primitives with success edges, extra edges, and end states."""
    count = draw(st.integers(1, max_states))
    state_names = draw(st.lists(names, min_size=count, max_size=count, unique=True).filter(
        lambda ns: not {"done", "failed"} & set(ns)))
    states = [draw(primitive_states(n, **state_kinds)) for n in state_names]
    roles = draw(st.sampled_from([(), ("holder",), ("holder", "worker")]))  # none: every older file
    if roles:  # with several roles each state names one; with one it may leave it out
        states = [s.model_copy(update={"role": draw(st.sampled_from(roles) if len(roles) > 1
                                                    else st.none() | st.just(roles[0]))}) for s in states]
    chain = state_names + ["done"]
    transitions = [Transition(origin=a, destination=b, events=(Event(type=EventType.SUCCESS),))
                   for a, b in zip(chain, chain[1:])]
    for origin in state_names:  # extra edges, never ambiguous: each with its own event set
        used = {frozenset([(EventType.SUCCESS, None)])}
        for _ in range(draw(st.integers(0, 2))):
            evs = tuple(draw(st.lists(events, min_size=1, max_size=2, unique_by=lambda e: e.type)))
            key = frozenset((e.type, e.seconds) for e in evs)
            if key not in used:
                used.add(key)
                transitions.append(Transition(origin=origin, destination=draw(st.sampled_from(chain + ["failed"])),
                                              events=evs))
    return Task(
        known_objects=tuple(draw(st.lists(objects(), max_size=1))),
        environment=draw(st.none() | st.builds(
            lambda obs: Environment(obstacles=tuple(obs)),
            st.lists(st.builds(lambda p, s: Obstacle(position=p, size=s),
                               st.tuples(coordinate, coordinate, coordinate),
                               st.none() | st.tuples(positive, positive, positive)), max_size=3))),
        roles=tuple(Role(name=r) for r in roles),
        states=tuple(states) + (State(name="done", type=StateType.SUCCESS), State(name="failed", type=StateType.FAILURE)),
        transitions=tuple(transitions),
    )
