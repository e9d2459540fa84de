"""The task graph as networkx holds it, built once per task for every check that walks it.

Nodes are state names; each edge is one transition, keyed by its id, and carries the
values written along it: a perceptual state writes its values only when it leaves on its
finding event (`object_found`, `contact`), so a value read after a perceive that found
nothing was never written. `available` is the data-flow analysis over those edges.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass
from functools import cached_property

import networkx as nx

from atd.model.task import State, Task
from atd.model.vocabulary import FINDING_EVENT


def written_on_leaving(state: State | None, events: set) -> frozenset[str]:
    """The values a state writes when it leaves on `events` (event types, all holding)."""
    if state is None or not state.writes or FINDING_EVENT.get(state.type) not in events:
        return frozenset()
    return frozenset(v.name for v in state.writes)


@dataclass(frozen=True)
class TaskGraph:
    """One task's states and transitions as a networkx MultiDiGraph."""

    task: Task

    @cached_property
    def graph(self) -> nx.MultiDiGraph:
        graph = nx.MultiDiGraph()
        states = self.task.states_by_name
        graph.add_nodes_from(states)
        graph.add_edges_from(
            (t.origin, t.destination, tid,
             {"writes": written_on_leaving(states.get(t.origin), {e.type for e in t.events})})
            for tid, t in zip(self.task.transition_ids, self.task.transitions))
        return graph

    @property
    def start(self) -> str | None:
        start = self.task.initial_state
        return start if start in self.task.states_by_name else None

    def leaving(self, name: str) -> int:
        """How many transitions leave a state."""
        return self.graph.out_degree(name)

    @cached_property
    def reached(self) -> set[str]:
        """The states the initial state leads to, itself included."""
        if self.start is None:
            return set()
        return {self.start} | nx.descendants(self.graph, self.start)

    @cached_property
    def finishing(self) -> set[str]:
        """The states from which some end state can be reached, the end states included."""
        ends = [s.name for s in self.task.states if s.type.is_end]
        if not ends:
            return set()
        return set(nx.multi_source_dijkstra_path_length(self.graph.reverse(copy=False), ends))

    @cached_property
    def available(self) -> dict[str, frozenset[str]]:
        """For each state the initial state reaches, the values written on every path to it
        (the task's inputs are written before it starts): a must-analysis, iterated from the
        start until nothing changes; each set only shrinks, so it ends."""
        if self.start is None:
            return {}
        inputs = frozenset(v.name for v in self.task.inputs)
        found = {self.start: inputs}
        queue = deque([self.start])
        while queue:
            origin = queue.popleft()
            before = found[origin]
            for _, destination, writes in self.graph.out_edges(origin, data="writes"):
                arriving = before | writes
                known = found.get(destination)
                meet = arriving if known is None else known & arriving
                if destination == self.start:
                    meet &= inputs
                if meet != known:
                    found[destination] = meet
                    queue.append(destination)
        return found

    def unwritten_path(self, value: str, reader: str) -> list[str]:
        """A way from the initial state to `reader` along which `value` is never written."""
        graph = self.graph
        view = nx.subgraph_view(graph, filter_edge=lambda u, v, k: value not in graph.edges[u, v, k]["writes"])
        return nx.shortest_path(view, self.start, reader)
