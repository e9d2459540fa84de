"""The library layout: what a reader of the picture relies on, checked on geometry."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given, settings

from atd.graph.layout import MAX_ELEMENTS, Layout, PictureTooBig, Rect, layout
from atd.graph.model import Edge, Graph, Node, NodeKind, from_task
from atd.graph.text import text_size
from atd.model import load_task
from tests.conftest import EXAMPLES, KNOWN_BOX
from tests.model.strategies import tasks

EPS = 1e-6


def example_graph(name: str, folder: Path = EXAMPLES) -> Graph:
    task, found = load_task(folder / name)
    assert task is not None, found
    return from_task(task, name)


def overlap(a: Rect, b: Rect) -> bool:
    return a.x < b.right - EPS and b.x < a.right - EPS and a.y < b.bottom - EPS and b.y < a.bottom - EPS


def inside(point: tuple[float, float], r: Rect) -> bool:
    return r.x + EPS < point[0] < r.right - EPS and r.y + EPS < point[1] < r.bottom - EPS


def on_border(point: tuple[float, float], box: Rect) -> bool:
    x, y = point
    return box.x - EPS <= x <= box.right + EPS and (abs(y - box.y) < EPS or abs(y - box.bottom) < EPS)


def assert_readable(graph: Graph) -> Layout:
    """Every state has a box big enough for its text and every transition an arrow with a label
    big enough for its text; no two boxes overlap, no label covers a box or another label; arrows
    start and end on the boxes they connect and pass through no box on the way."""
    drawing = layout(graph)
    assert set(drawing.boxes) == {n.id for n in graph.nodes}
    assert sorted(r.edge.id for r in drawing.routes) == sorted(e.id for e in graph.edges)
    boxes = list(drawing.boxes.values())
    for box in boxes:
        width, height = text_size(box.node.lines)
        assert box.width > width and box.height > height
    labels = [r.label for r in drawing.routes]
    for route in drawing.routes:
        width, height = text_size(route.edge.lines)
        assert route.label.width > width and route.label.height > height
    for i, a in enumerate(boxes):
        assert not any(overlap(a, b) for b in boxes[i + 1:]), "boxes overlap"
        assert not any(overlap(a, label) for label in labels), "a label covers a box"
    for i, a in enumerate(labels):
        assert not any(overlap(a, b) for b in labels[i + 1:]), "labels overlap"
    for route in drawing.routes:
        if route.loop:
            source = drawing.boxes[route.edge.source]
            assert all(p[0] >= source.right - EPS for p in route.points)
            continue
        assert on_border(route.points[0], drawing.boxes[route.edge.source])
        assert on_border(route.points[-1], drawing.boxes[route.edge.target])
        between = route.points[1:-1]
        assert not any(inside(p, b) for p in between for b in boxes), f"arrow {route.edge.id} runs through a box"
        ys = [p[1] for p in route.points]
        assert ys == sorted(ys) or ys == sorted(ys, reverse=True), f"arrow {route.edge.id} turns back"
    assert all(r.x >= 0 and r.y >= 0 and r.right <= drawing.width and r.bottom <= drawing.height
               for r in boxes + labels)
    return drawing


def test_pick_and_place_reads_top_to_bottom():
    drawing = assert_readable(example_graph("pick_and_place.xml"))
    chain = ["approach", "descend", "grasp", "lift", "carry", "put_down", "let_go", "retreat", "done"]
    tops = [drawing.boxes[name].y for name in chain]
    assert tops == sorted(tops) and len(set(tops)) == len(tops)
    assert drawing.boxes["failed"].y == drawing.boxes["done"].y  # the longest path sets both end states


def test_the_arrows_into_the_failure_state_stay_apart():
    drawing = layout(example_graph("pick_and_place.xml"))
    ends = sorted(r.points[-1][0] for r in drawing.routes if r.edge.target == "failed")
    assert len(ends) == 18
    assert min(b - a for a, b in zip(ends, ends[1:])) >= 9.0


def test_retry_loops_run_upwards_into_their_target():
    graph = example_graph("retry_grasp.xml")
    drawing = assert_readable(graph)
    for retry in ("grasp->approach", "lift->approach"):
        route = next(r for r in drawing.routes if r.edge.id == retry)
        source, target = drawing.boxes[route.edge.source], drawing.boxes["approach"]
        assert route.points[0][1] == source.y  # leaves the top of its source
        assert route.points[-1][1] == target.bottom  # arrives at the bottom of approach
    lift = next(r for r in drawing.routes if r.edge.id == "lift->approach")
    assert drawing.boxes["approach"].bottom < lift.label.y < drawing.boxes["lift"].y


def test_self_loop_sits_beside_its_state():
    drawing = assert_readable(example_graph("empty_the_box.xml", KNOWN_BOX))
    loop = next(r for r in drawing.routes if r.loop)
    box = drawing.boxes["pick_one"]
    assert loop.edge.id == "pick_one->pick_one"
    assert loop.label.x > box.right and box.y <= loop.label.y <= box.bottom


def test_parallel_transitions_and_unconnected_states_each_get_their_own_place():
    a, b, c = (Node(name, (name,), NodeKind.PRIMITIVE, name == "a") for name in "abc")
    graph = Graph("t", [a, b, c], [Edge("a", "b", ("success",), "a->b"), Edge("a", "b", ("error",), "a->b#2"),
                                    Edge("b", "b", ("timeout(1s)",), "b->b"), Edge("b", "b", ("error",), "b->b#2")])
    drawing = assert_readable(graph)
    assert drawing.boxes["c"].x > drawing.boxes["b"].right  # a part of its own, beside the rest
    loops = [r for r in drawing.routes if r.loop]
    assert max(p[0] for p in loops[1].points) > max(p[0] for p in loops[0].points)  # nested, not on top


def test_a_task_too_big_to_lay_out_is_refused_before_trying():
    nodes = [Node(f"s{k}", (f"s{k}",), NodeKind.PRIMITIVE, k == 0) for k in range(MAX_ELEMENTS // 2 + 1)]
    edges = [Edge(f"s{k}", f"s{k + 1}", ("success",), f"e{k}") for k in range(len(nodes) - 1)]
    with pytest.raises(PictureTooBig, match=r"601 states and 600 transitions .* install graphviz, or write \.dot"):
        layout(Graph("big", nodes, edges))


@settings(max_examples=40, deadline=None)
@given(tasks())
def test_any_valid_task_is_drawn_readably(task):
    assert_readable(from_task(task, "generated.xml"))
