"""The three translation rules (thesis 7.2.2) and full traceability, checked on a result.

1. Each node in the ATD corresponds to one node in the ESTD.
2. Each edge in the ATD corresponds to one edge in the ESTD.
3. Each edge label (abstract event) is represented by one or more concrete conditions
   (an ESTD event holds one condition tree, and a group cannot be empty, so it suffices
   that each ATD event has its own ESTD event).

Plus what makes the result traceable and runnable: every ESTD state, transition, event
and condition carries the id of its ATD element; every primitive state has an arm and a
hand controller, every sub-task state its machine. The translator runs this on each
machine it builds and refuses to emit one that fails; tests run it on generated tasks.
"""

from __future__ import annotations

from collections import Counter

from atd.model.estd import Estd, leaves
from atd.model.task import Task
from atd.model.vocabulary import StateType


def event_ids(transition_id: str, event_types: list[str]) -> list[str]:
    """Trace ids of the events of one edge: `<edge id>/<event>`, `#n` only among repeats."""
    if len(set(event_types)) == len(event_types):
        return [f"{transition_id}/{kind}" for kind in event_types]
    totals = Counter(event_types)
    seen: Counter[str] = Counter()
    ids = []
    for kind in event_types:
        seen[kind] += 1
        ids.append(f"{transition_id}/{kind}" + (f"#{seen[kind]}" if totals[kind] > 1 else ""))
    return ids


def check_rules(task: Task, estd: Estd) -> list[str]:
    """Every way `estd` (one machine, not its sub-machines) breaks the rules for `task`."""
    problems: list[str] = []
    if len(estd.states) != len(task.states):
        problems.append(f"rule 1: the ATD has {len(task.states)} states, the ESTD {len(estd.states)}")
    for atd_state, state in zip(task.states, estd.states):
        if (state.atd, state.name, state.type) != (atd_state.name, atd_state.name, atd_state.type):
            problems.append(f"rule 1: ESTD state '{state.name}' ({state.type.value}, from '{state.atd}') does not "
                            f"match ATD state '{atd_state.name}' ({atd_state.type.value})")
        elif state.type.is_end and (state.arm or state.hand or state.machine):
            problems.append(f"end state '{state.name}' runs controllers")
        elif state.type is StateType.TASK and state.machine is None:
            problems.append(f"sub-task state '{state.name}' has no machine")
        elif not state.type.is_end and state.type is not StateType.TASK and (state.arm is None or state.hand is None):
            problems.append(f"state '{state.name}' lacks an arm or a hand controller")
    if len(estd.transitions) != len(task.transitions):
        problems.append(f"rule 2: the ATD has {len(task.transitions)} transitions, the ESTD {len(estd.transitions)}")
    for tid, atd_edge, edge in zip(task.transition_ids, task.transitions, estd.transitions):
        if (edge.atd, edge.origin, edge.destination) != (tid, atd_edge.origin, atd_edge.destination):
            problems.append(f"rule 2: ESTD transition '{edge.atd}' ({edge.origin} -> {edge.destination}) does not "
                            f"match ATD transition '{tid}'")
            continue
        types = [e.type.value for e in atd_edge.events]
        if [e.type.value for e in edge.events] != types:
            problems.append(f"rule 3: transition '{tid}' has events {types} in the ATD but "
                            f"{[e.type.value for e in edge.events]} in the ESTD")
            continue
        for expected, event in zip(event_ids(tid, types), edge.events):
            found = leaves(event.condition)
            if event.atd != expected:
                problems.append(f"trace: event '{event.atd}' should carry '{expected}'")
            stray = [leaf.kind for leaf in found if leaf.atd != expected]
            if stray:
                problems.append(f"trace: conditions {stray} of event '{expected}' do not carry its id")
    return problems
