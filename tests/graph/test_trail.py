"""A run's path on its task's graph: in colour, the rest grey, untaken failure arrows folded, in both renderers."""

from __future__ import annotations

import re
from collections import Counter

from lxml import etree

from atd.graph.dot import to_dot
from atd.graph.layout import layout
from atd.graph.model import NodeKind, Trail
from atd.graph.style import FADED_BORDER, FADED_FILL, PALETTE, TAKEN_WIDTH
from atd.graph.svg import to_svg
from atd.graph.trail import on_trail
from tests.graph.test_layout import example_graph
from tests.graph.test_render import SVG

PATH = ["approach", "descend", "grasp", "lift", "carry", "put_down", "let_go", "retreat", "done"]
TAKEN = Counter({f"{a}->{b}": 1 for a, b in zip(PATH, PATH[1:])})


def _marked():
    graph = example_graph("pick_and_place.xml")
    return graph, *on_trail(graph, set(PATH), TAKEN)


def test_the_untaken_failure_fan_folds_to_one_grey_arrow_per_state() -> None:
    graph, marked, folded = _marked()
    into_failed = [e for e in graph.edges if e.target == "failed"]
    assert len(into_failed) == 18  # the fan the page used to draw
    folds = [e for e in marked.edges if e.target == "failed"]
    assert {e.source for e in folds} == {"approach", "descend", "grasp", "lift", "carry", "put_down", "let_go",
                                         "retreat"}
    assert len(folds) == 8 and all(e.trail is Trail.FADED for e in folds)
    carry = next(e for e in folds if e.source == "carry")
    assert carry.lines == ("5 failure transitions",)  # grasp_lost, collision, timeout, hardware_failure, error
    assert folded.transitions == 15 and folded.arrows == 5  # descend, let_go and retreat have one each: drawn as is
    assert [e.trail for e in marked.edges if e.target != "failed"] == [Trail.TAKEN] * len(TAKEN)
    assert {n.id: n.trail for n in marked.nodes}["failed"] is Trail.FADED


def test_a_transition_taken_again_says_how_often() -> None:
    graph = example_graph("pick_and_place.xml")
    marked, _ = on_trail(graph, set(PATH), TAKEN + Counter({"grasp->lift": 2}))
    assert next(e for e in marked.edges if e.id == "grasp->lift").lines[-1] == "taken 3x"


def test_dot_greys_what_was_not_visited_and_thickens_what_was_taken() -> None:
    _, marked, _ = _marked()
    dot = to_dot(marked)
    failed = next(line for line in dot.splitlines() if line.startswith('  "failed" ['))
    assert f'fillcolor="{FADED_FILL}"' in failed and f'color="{FADED_BORDER}"' in failed
    grasp = next(line for line in dot.splitlines() if line.startswith('  "grasp" ['))
    assert f'fillcolor="{PALETTE[NodeKind.PRIMITIVE][0]}"' in grasp
    taken = next(line for line in dot.splitlines() if line.startswith('  "grasp" -> "lift"'))
    assert f"penwidth={TAKEN_WIDTH:g}" in taken
    folds = [line for line in dot.splitlines() if re.match(r'  "\w+" -> "failed"', line)]
    assert len(folds) == 8 and all(f'color="{FADED_BORDER}"' in line for line in folds)


def test_svg_greys_what_was_not_visited_and_thickens_what_was_taken() -> None:
    _, marked, _ = _marked()
    root = etree.fromstring(to_svg(layout(marked)))
    boxes = {g.get("data-state"): g.find(f"{SVG}rect").get("fill") for g in root.iter(f"{SVG}g")
             if g.get("class") == "state"}
    assert boxes["failed"] == FADED_FILL and boxes["grasp"] == PALETTE[NodeKind.PRIMITIVE][0]
    arrows = [g for g in root.iter(f"{SVG}g") if g.get("class") == "edge"]
    widths = {g.get("data-transition"): float(g.find(f"{SVG}path").get("stroke-width")) for g in arrows}
    assert widths["grasp->lift"] == TAKEN_WIDTH
    grey = [g for g in arrows if g.find(f"{SVG}path").get("stroke") == FADED_BORDER]
    assert len(grey) == 8 and all(g.find(f"{SVG}path").get("marker-end") == "url(#arrowhead-faded)" for g in grey)
    assert "5 failure transitions" in {t.text for g in grey for t in g.iter(f"{SVG}text")}
