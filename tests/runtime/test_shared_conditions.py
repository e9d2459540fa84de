"""A condition that several events of a state name alike is built once and asked once a tick:
its timer counts each tick once, so it holds after its `for_time` as if each event had its own."""

from __future__ import annotations

from atd.model.estd import ConditionGroup, Estd, EstdEvent, EstdState, EstdTransition
from atd.model.vocabulary import EventType, StateType
from tests.primitives.conftest import events, execute, leaf, melfa, use

FOR_TIME = 0.3  # s the arm must have been done before either event holds


def _edge(destination: str, event: EventType, condition) -> EstdTransition:
    atd = f"hold->{destination}"
    return EstdTransition(origin="hold", destination=destination, atd=atd,
                          events=(EstdEvent(type=event, atd=f"{atd}/{event.value}", condition=condition),))


def test_a_debounced_leaf_in_two_events_holds_after_its_time_and_both_see_it() -> None:
    done_for = leaf("arm_done", for_time=FOR_TIME)
    estd = Estd(robot="melfa", arm="main", initial="hold", states=(
        EstdState(name="hold", type=StateType.MOVE, atd="hold", arm=use("hold"), hand=use("hold_position")),
        EstdState(name="done", type=StateType.SUCCESS, atd="done"),
        EstdState(name="failed", type=StateType.FAILURE, atd="failed"),
    ), transitions=(
        # The first edge also waits for a timeout long after FOR_TIME: the second edge, which asks
        # for the same leaf alone, fires first.
        _edge("failed", EventType.ERROR, ConditionGroup(op="all", children=(done_for, leaf("timeout", seconds=5.0)))),
        _edge("done", EventType.SUCCESS, done_for),
    ))
    outcome, executor = execute(estd, melfa())
    assert outcome.succeeded, outcome.summary
    fired = events(executor)
    assert [e["transition"] for e in fired] == ["hold->done"]
    held_for = fired[0]["conditions"][0]["held_for"]
    assert abs(held_for - FOR_TIME) < 1e-6, held_for
    assert abs(outcome.sim_time - FOR_TIME) < 0.011, outcome.sim_time
