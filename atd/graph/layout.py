"""Where boxes, arrows and labels go when graphviz is absent: grandalf's layered (Sugiyama) layout.

grandalf places vertices of given sizes in layers, orders them against crossings and routes
long edges through dummy vertices. What it does not know about, we add around it:

- Labels: each transition A -> B is laid out as A -> label -> B through a vertex the size of
  its label, so layers of states alternate with layers of labels (as graphviz draws them) and
  every label gets a place of its own that no box or other label covers.
- Cycles: grandalf's depth-first search from the initial state marks the transitions that close
  a cycle (a retry); both halves of such a transition are laid out turned round, so it runs
  upwards from its source into its target with its label on the way.
- Self-loops stay out of grandalf: they are curves on the right of their box, whose vertex is
  widened on both sides to make room for them and their labels.
"""

from __future__ import annotations

import math
from collections import Counter, defaultdict
from dataclasses import dataclass, field, replace

from grandalf.graphs import Edge as LinkEdge
from grandalf.graphs import Graph as LinkGraph
from grandalf.graphs import Vertex, graph_core
from grandalf.layouts import SugiyamaLayout, VertexViewer

from atd.graph.model import Edge, Graph, Node
from atd.graph.text import LINE_HEIGHT, text_size

Point = tuple[float, float]

# grandalf's time grows with the square of the task (a generated 300-state, 900-transition task
# takes about 10 s); beyond this many states and transitions graphviz is the tool.
MAX_ELEMENTS = 1200
NODE_GAP = 24.0  # between a box or label and its neighbour in a layer
ARROW_LANE = 12.0  # between two arrows passing through a layer
LAYER_GAP = 24.0  # between layers, where arrows bend ...
BEND_SLOPE = 0.2  # ... plus this much of the farthest any of them runs sideways,
MAX_LAYER_GAP = 90.0  # up to this, so they cross as curves rather than flat lines
PAD_X, PAD_Y = 8.0, 5.0  # text to box border
LABEL_PAD = 3.0  # text to the edge of its label's background
LOOP_REACH, LOOP_STEP = 26.0, 12.0  # how far the first self-loop sticks out, and each next one further
PORT_SPACING = 10.0  # between arrows meeting one side of a box
MARGIN = 16.0
COMPONENT_GAP = 40.0  # between parts of the task no transition joins


class PictureTooBig(ValueError):
    """The task is too big to lay out, or to rasterise; the message says what to draw instead."""


@dataclass(frozen=True)
class Rect:
    x: float  # top-left corner
    y: float
    width: float
    height: float

    @property
    def right(self) -> float:
        return self.x + self.width

    @property
    def bottom(self) -> float:
        return self.y + self.height


@dataclass(frozen=True)
class Box(Rect):
    node: Node


@dataclass(frozen=True)
class Route:
    """One arrow. An ordinary arrow passes through `points` from layer to layer, leaving and
    entering each one vertically; a self-loop's `points` are one cubic Bezier curve."""

    edge: Edge
    points: tuple[Point, ...]
    loop: bool
    label: Rect  # the label's background; the arrow runs under it


@dataclass
class Layout:
    width: int  # whole pixels, so a PNG's size is exactly this times its scale
    height: int
    title: str
    boxes: dict[str, Box] = field(default_factory=dict)
    routes: list[Route] = field(default_factory=list)


class _Path:
    """grandalf's edge viewer protocol: the layout hands each edge its points through `setpath`."""

    def __init__(self) -> None:
        self.points: list[Point] = []

    def setpath(self, points: list[Point]) -> None:
        self.points = points


@dataclass
class _Transition:
    edge: Edge
    label: Vertex
    halves: tuple[LinkEdge, LinkEdge]  # source -> label, label -> target


def box_size(node: Node, arrows: int) -> tuple[float, float]:
    """Room for the text, and along the top and bottom for the most `arrows` one side meets
    (they are spread over the middle 80%), so the arrows into a failure state stay apart."""
    width, height = text_size(node.lines)
    return max(width + 2 * PAD_X, PORT_SPACING * (arrows + 1) / 0.8), height + 2 * PAD_Y


def label_size(edge: Edge) -> tuple[float, float]:
    width, height = text_size(edge.lines)
    return width + 2 * LABEL_PAD, height + 2 * LABEL_PAD


def layout(graph: Graph) -> Layout:
    """Boxes and arrows for `graph` in pixels, top-left origin, the title above them."""
    if len(graph.nodes) + len(graph.edges) > MAX_ELEMENTS:
        raise PictureTooBig(f"{len(graph.nodes)} states and {len(graph.edges)} transitions are more than the "
                            f"library layout draws in good time ({MAX_ELEMENTS} in all); install graphviz, or "
                            "write .dot and draw it elsewhere")
    loops: dict[str, list[Edge]] = defaultdict(list)
    for edge in graph.edges:
        if edge.source == edge.target:
            loops[edge.source].append(edge)
    leaving = Counter(e.source for e in graph.edges if e.source != e.target)
    entering = Counter(e.target for e in graph.edges if e.source != e.target)
    sizes = {node.id: box_size(node, max(leaving[node.id], entering[node.id])) for node in graph.nodes}
    states = {node.id: _state_vertex(node, sizes[node.id], loops.get(node.id, [])) for node in graph.nodes}
    transitions = []
    for edge in graph.edges:
        if edge.source != edge.target:
            label = _vertex(edge, *label_size(edge))
            transitions.append(_Transition(edge, label, (LinkEdge(states[edge.source], label),
                                                         LinkEdge(label, states[edge.target]))))
    links = LinkGraph(list(states.values()) + [t.label for t in transitions],
                      [half for t in transitions for half in t.halves])
    initial = next((states[n.id] for n in graph.nodes if n.initial), None)
    left, top = MARGIN - NODE_GAP / 2, MARGIN + LINE_HEIGHT + MARGIN  # below the title
    for part in links.C:
        left = _place(part, transitions, initial, left, top) + COMPONENT_GAP
    drawing = Layout(0, 0, graph.title)
    for node in graph.nodes:
        (cx, cy), (width, height) = states[node.id].view.xy, sizes[node.id]
        drawing.boxes[node.id] = Box(cx - width / 2, cy - height / 2, width, height, node)
    drawing.routes = _attach([_route(t) for t in transitions], drawing.boxes)
    for name, edges in loops.items():
        drawing.routes += _self_loops(drawing.boxes[name], edges)
    corners = [(r.right, r.bottom) for r in [*drawing.boxes.values(), *(r.label for r in drawing.routes)]]
    drawing.width = math.ceil(max([x for x, _ in corners] + [MARGIN + text_size((graph.title,))[0]]) + MARGIN)
    drawing.height = math.ceil(max([y for _, y in corners] + [top]) + MARGIN)
    return drawing


def _vertex(data: Node | Edge, width: float, height: float) -> Vertex:
    vertex = Vertex(data)
    vertex.view = VertexViewer(width + NODE_GAP, height)  # grandalf keeps only arrow lanes apart
    return vertex


def _state_vertex(node: Node, size: tuple[float, float], loops: list[Edge]) -> Vertex:
    """A box, widened on both sides (it stays centred) by the reach of its self-loops."""
    width, height = size
    if loops:
        room = LOOP_REACH + LOOP_STEP * (len(loops) - 1) + LABEL_PAD + max(label_size(e)[0] for e in loops)
        width += 2 * room
        height = max(height, sum(label_size(e)[1] for e in loops))
    return _vertex(node, width, height)


def _place(part: graph_core, transitions: list[_Transition], initial: Vertex | None, left: float, top: float) -> float:
    """Lay out one connected part of the task from `left`, `top`; returns the part's right edge."""
    roots = [initial] if initial is not None and initial in part.sV else None
    part.get_scs_with_feedback(roots)  # marks the halves that close a cycle
    turned = [half for t in transitions if any(h.feedback for h in t.halves) for half in t.halves
              if half in part.sE]
    for half in part.sE:
        half.view = _Path()
    sugiyama = SugiyamaLayout(part)
    sugiyama.xspace, sugiyama.yspace = 0.0, LAYER_GAP
    sugiyama.dw, sugiyama.dh = ARROW_LANE, 0.0  # the dummy vertices long arrows pass through
    sugiyama.init_all(roots=roots, inverted_edges=turned)
    sugiyama.draw()
    vertices = list(part.sV)
    shift_x = left - min(v.view.xy[0] - v.view.w / 2 for v in vertices)
    shift_y = _bend_room(part, [layer[0].view.xy[1] for layer in sugiyama.layers], top)
    for vertex in vertices:
        vertex.view.xy = (vertex.view.xy[0] + shift_x, shift_y[vertex.view.xy[1]])
    for half in part.sE:
        half.view.points = [(x + shift_x, shift_y[y]) for x, y in half.view.points]
    return max(v.view.xy[0] + v.view.w / 2 for v in vertices)


def _bend_room(part: graph_core, layers: list[float], top: float) -> dict[float, float]:
    """Where each layer's middle moves to: down by `top`, and by the room the gaps above it
    were given for arrows that run far sideways across them."""
    widest = [0.0] * len(layers)  # how far sideways an arrow runs from this layer to the next
    upper = {y: k for k, y in enumerate(layers)}
    for half in part.sE:
        for (xa, ya), (xb, yb) in zip(half.view.points, half.view.points[1:]):
            k = upper[min(ya, yb)]
            widest[k] = max(widest[k], abs(xb - xa))
    moved, extra = {}, top
    for y, run in zip(layers, widest):
        moved[y] = y + extra
        extra += min(MAX_LAYER_GAP, max(LAYER_GAP, BEND_SLOPE * run)) - LAYER_GAP
    return moved


def _route(transition: _Transition) -> Route:
    """The arrow from centre to centre through its label; `_attach` puts its ends on the boxes."""
    first, second = (half.view.points for half in transition.halves)
    (cx, cy), (width, height) = transition.label.view.xy, label_size(transition.edge)
    label = Rect(cx - width / 2, cy - height / 2, width, height)
    return Route(transition.edge, tuple(first + second[1:]), False, label)


def _attach(routes: list[Route], boxes: dict[str, Box]) -> list[Route]:
    """Arrow ends on the box borders, on the side facing the arrow's next point and spread along
    it in the order of those points, so the many arrows into a failure state do not pile up."""
    ends: dict[tuple[str, bool], list[tuple[float, int, int]]] = defaultdict(list)
    for k, route in enumerate(routes):
        for end, state, near in ((0, route.edge.source, route.points[1]), (-1, route.edge.target, route.points[-2])):
            box = boxes[state]
            ends[(state, near[1] > box.y + box.height / 2)].append((near[0], k, end))
    points = [list(route.points) for route in routes]
    for (state, below), found in ends.items():
        box = boxes[state]
        for rank, (_, k, end) in enumerate(sorted(found)):
            x = box.x + box.width * (0.1 + 0.8 * (rank + 1) / (len(found) + 1))
            points[k][end] = (x, box.bottom if below else box.y)
    return [replace(route, points=tuple(p)) for route, p in zip(routes, points)]


def _self_loops(box: Box, loops: list[Edge]) -> list[Route]:
    """Nested curves on the right of the box, their labels stacked beside the outermost."""
    routes = []
    middle = box.y + box.height / 2
    label_x = box.right + LOOP_REACH + LOOP_STEP * (len(loops) - 1) + LABEL_PAD
    label_y = middle - sum(label_size(e)[1] for e in loops) / 2
    for k, edge in enumerate(loops):
        reach = (LOOP_REACH + LOOP_STEP * k) / 0.75  # a cubic reaches 3/4 of the way to its control points
        rise = min(box.height / 2 - 3, 4 + 9 * k)  # arrowheads 9 px apart
        bulge = rise + 8 + 4 * k
        points = ((box.right, middle - rise), (box.right + reach, middle - bulge),
                  (box.right + reach, middle + bulge), (box.right, middle + rise))
        width, height = label_size(edge)
        routes.append(Route(edge, points, True, Rect(label_x, label_y, width, height)))
        label_y += height
    return routes
