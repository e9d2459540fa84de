"""The built-in layout: what a reader of the picture relies on, checked on geometry."""

from __future__ import annotations

from hypothesis import given, settings

from atd.graph.layout import Box, Layout, Metrics, find_back_edges, layout, longest_path_layers
from atd.graph.model import Graph, from_task
from atd.graph.svg import SVG_METRICS
from atd.model import load_task
from tests.conftest import EXAMPLES
from tests.model.strategies import tasks

Rect = tuple[float, float, float, float]  # x0, y0, x1, y1
EPS = 1e-6


def example_graph(name: str) -> Graph:
    task, found = load_task(EXAMPLES / name)
    assert task is not None, found
    return from_task(task, name)


def overlap(a: Rect, b: Rect) -> bool:
    return a[0] < b[2] - EPS and b[0] < a[2] - EPS and a[1] < b[3] - EPS and b[1] < a[3] - EPS


def rect(box: Box) -> Rect:
    return (box.x, box.y, box.right, box.bottom)


def label_rects(drawing: Layout, metrics: Metrics) -> list[Rect]:
    out = []
    for route in drawing.routes:
        width, height = metrics.text_size(route.edge.lines)
        out.append((route.label_at[0], route.label_at[1], route.label_at[0] + width, route.label_at[1] + height))
    return out


def inside(point: tuple[float, float], r: Rect) -> bool:
    return r[0] + EPS < point[0] < r[2] - EPS and r[1] + EPS < point[1] < r[3] - EPS


def on_border(point: tuple[float, float], box: Box) -> bool:
    x, y = point
    return box.x - EPS <= x <= box.right + EPS and (abs(y - box.y) < EPS or abs(y - box.bottom) < EPS)


def assert_readable(graph: Graph, metrics: Metrics = SVG_METRICS) -> Layout:
    """No two boxes overlap, no label covers a box or another label, arrows run between boxes and
    start and end on the boxes they connect."""
    drawing = layout(graph, metrics)
    assert set(drawing.boxes) == {n.id for n in graph.nodes}
    assert len(drawing.routes) == len(graph.edges)
    boxes = [rect(b) for b in drawing.boxes.values()]
    labels = label_rects(drawing, metrics)
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
        middle = list(route.points[1:-1])
        middle += [((a[0] + b[0]) / 2, (a[1] + b[1]) / 2) for a, b in zip(middle, middle[1:]) if a[0] == b[0]]
        assert not any(inside(p, r) for p in middle for r in boxes), f"arrow {route.edge.id} runs through a box"
    assert all(r[2] <= drawing.width + EPS and r[3] <= drawing.height + EPS for r in boxes + labels)
    return drawing


def test_pick_and_place_reads_top_to_bottom():
    drawing = assert_readable(example_graph("pick_and_place.xml"))
    chain = ["approach", "descend", "grasp", "lift", "carry", "put_down", "let_go", "retreat", "done"]
    tops = [drawing.boxes[name].y for name in chain]
    assert tops == sorted(tops) and len(set(tops)) == len(tops)
    assert drawing.boxes["failed"].y == drawing.boxes["done"].y  # the longest path sets both end states


def test_retry_loops_are_back_edges_drawn_upwards():
    graph = example_graph("retry_grasp.xml")
    back = {graph.edges[i].id for i in find_back_edges(graph, "approach")}
    assert back == {"grasp->approach", "lift->approach"}
    layers = longest_path_layers(graph, find_back_edges(graph, "approach"))
    assert layers["approach"] == 0 and layers["lift"] == 3
    drawing = assert_readable(graph)
    retry = next(r for r in drawing.routes if r.edge.id == "lift->approach")
    assert retry.points[0][1] > retry.points[-1][1]  # leaves lift's top, arrives at approach's bottom
    assert retry.points[-1][1] == drawing.boxes["approach"].bottom


def test_self_loop_sits_beside_its_state():
    drawing = assert_readable(example_graph("empty_the_box.xml"))
    loop = next(r for r in drawing.routes if r.loop)
    box = drawing.boxes["pick_one"]
    assert loop.edge.id == "pick_one->pick_one"
    assert loop.label_at[0] > box.right and box.y <= loop.label_at[1] <= box.bottom


@settings(max_examples=60, deadline=None)
@given(tasks())
def test_any_valid_task_is_drawn_readably(task):
    assert_readable(from_task(task, "generated.xml"))
