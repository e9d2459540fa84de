"""From a file to a `Graph`: tell an ATD from an ESTD by its root element, read it, check it."""

from __future__ import annotations

from pathlib import Path

from atd.graph.model import Graph, from_estd, from_task
from atd.model.diagnostics import Diagnostic, error, has_errors
from atd.model.estd_xml import is_estd_file, read_estd
from atd.model.load import load_task
from atd.model.task import Location
from atd.model.xmlsafe import read_file

ATD_ROOT = "statemachine"


def read_graph(path: Path, conditions: bool = False, all_params: bool = False) -> tuple[Graph | None, list[Diagnostic]]:
    """The graph of the ATD or ESTD in `path`, or None and the reasons it cannot be drawn.

    Only a file that passes its language's checks is drawn, so a picture never shows a
    task that `atd translate` or `atd run` would refuse.
    """
    if is_estd_file(path):
        return _estd(path, conditions, all_params)
    doc, found = read_file(path)
    if doc is None:
        return None, found
    if doc.root.tag == ATD_ROOT:
        task, found = load_task(path)
        if task is None or has_errors(found):
            return None, found
        return from_task(task, str(path)), found
    return None, [error("GRF001", f"root element is <{doc.root.tag}>, neither <{ATD_ROOT}> (an ATD) nor "
                        "<estd> (an ESTD)", doc.loc(doc.root),
                        "atd graph draws task files (see docs/atd-format.md) and the ESTDs atd translate writes")]


def _estd(path: Path, conditions: bool, all_params: bool) -> tuple[Graph | None, list[Diagnostic]]:
    estd, found = read_estd(path)
    if estd is None:
        return None, found
    graph = from_estd(estd, str(path), conditions, all_params)
    problems = dangling(graph)
    if problems:
        return None, [error("GRF002", p, Location(str(path), 0, 0), "was the file edited by hand? translate the "
                            "ATD again") for p in problems]
    return graph, found


def dangling(graph: Graph) -> list[str]:
    """Transitions that name a state the file does not define; an ESTD's schema cannot catch these."""
    names = {node.id for node in graph.nodes}
    return [f"transition '{edge.id}' names state '{end}', which is not defined"
            for edge in graph.edges for end in (edge.source, edge.target) if end not in names]
