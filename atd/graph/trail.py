"""A run drawn on its task's graph: the states it visited and the transitions it took in
colour (those taken thicker), the rest grey; and the failure transitions it never took
folded, one grey arrow per pair of states, so that the fan of arrows into a failure state
(a timeout and an error from every state) no longer hides the path."""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, replace

from atd.graph.model import Edge, Graph, NodeKind, Trail


@dataclass(frozen=True)
class Folded:
    """What `on_trail` left out: `transitions` never taken, drawn as `arrows` grey arrows."""

    transitions: int
    arrows: int


def on_trail(graph: Graph, visited: set[str], taken: Counter[str]) -> tuple[Graph, Folded]:
    """`graph` with the run's path marked: `visited` state names, `taken` counts per
    transition id (a transition taken more than once says how often)."""
    failures = {node.id for node in graph.nodes if node.kind is NodeKind.FAILURE}
    nodes = [replace(node, trail=Trail.TAKEN if node.id in visited else Trail.FADED) for node in graph.nodes]
    groups: dict[tuple[str, str], list[Edge]] = {}
    edges: list[Edge | tuple[str, str]] = []  # a pair of states stands for its group, where its first edge was
    for edge in graph.edges:
        if edge.id in taken:
            more = (f"taken {taken[edge.id]}x",) if taken[edge.id] > 1 else ()
            edges.append(replace(edge, lines=edge.lines + more, trail=Trail.TAKEN))
        elif edge.target in failures:
            pair = (edge.source, edge.target)
            if pair not in groups:
                groups[pair] = []
                edges.append(pair)
            groups[pair].append(edge)
        else:
            edges.append(replace(edge, trail=Trail.FADED))
    drawn = [item if isinstance(item, Edge) else _fold(groups[item]) for item in edges]
    folds = [group for group in groups.values() if len(group) > 1]
    return (Graph(graph.title, nodes, drawn),
            Folded(sum(len(group) for group in folds), len(folds)))


def _fold(group: list[Edge]) -> Edge:
    """One grey arrow for the failure transitions of one pair of states; its tooltip names them."""
    first = group[0]
    if len(group) == 1:
        return replace(first, trail=Trail.FADED)
    return Edge(first.source, first.target, (f"{len(group)} failure transitions",),
                " | ".join(edge.id for edge in group), Trail.FADED)
