"""A layered drawing of a task graph without graphviz (the Sugiyama recipe, kept small).

1. A depth-first search from the initial state finds the back edges (loops such as
   "retry the grasp"); turned around, the rest is acyclic.
2. Longest-path layering: a state sits one layer below its lowest predecessor, so the
   main line of the task reads top to bottom.
3. Every edge is cut into one-rank pieces by dummy vertices, and every layer of states
   is followed by a rank of edge labels (as graphviz does), so arrows and labels get their
   own lanes and never run through a box.
4. Barycentre sweeps order each rank to remove crossings; the best order seen is kept.
5. Horizontal positions: each rank in turn is pulled towards its neighbours' positions
   with the minimum spacing kept exactly (isotonic regression, pool adjacent violators).

Self-loops are drawn as a curve on the right of their state, with their labels beside it.
Everything is measured in abstract units from `Metrics`, so the SVG and PNG writers can
each say how wide their characters are.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass, field
from typing import Callable

from atd.graph.model import Edge, Graph, Node

Point = tuple[float, float]

SWEEPS = 8  # barycentre passes (down and up alternately)
PLACEMENT_PASSES = 6  # horizontal placement passes
NODE_GAP = 28.0  # between a box and its neighbour in a rank
DUMMY_GAP = 12.0  # between two arrows passing through a rank
RANK_GAP = 22.0  # vertical room between ranks for the arrows to bend
LABEL_OFFSET = 5.0  # between an arrow and its label
LOOP_REACH = 26.0  # how far the first self-loop sticks out of its box
LOOP_STEP = 12.0  # how much further each next self-loop reaches
MARGIN = 16.0
PORT_SPACING = 10.0  # between two arrows meeting the same side of a box


@dataclass(frozen=True)
class Metrics:
    """Text size in layout units: monospaced characters and lines."""

    char_width: float
    line_height: float
    pad_x: float = 8.0
    pad_y: float = 5.0

    def text_size(self, lines: tuple[str, ...]) -> tuple[float, float]:
        return max((len(line) for line in lines), default=0) * self.char_width, len(lines) * self.line_height


@dataclass(frozen=True)
class Box:
    node: Node
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
class Route:
    """How to draw one edge.

    For an ordinary edge `points` is a path whose pieces the renderers join with vertical
    S-curves (each piece leaves and arrives vertically); for a self-loop it is the four
    points of one cubic Bezier. The arrowhead goes at the last point.
    """

    edge: Edge
    points: tuple[Point, ...]
    loop: bool
    label_at: Point  # top-left of the label text


@dataclass
class Layout:
    width: float
    height: float
    title: str
    title_at: Point
    boxes: dict[str, Box] = field(default_factory=dict)
    routes: list[Route] = field(default_factory=list)


@dataclass
class _Vertex:
    """A box, or a dummy an edge passes through (with the edge's label beside it, if any)."""

    rank: int
    left: float  # extent left of the line/centre
    right: float
    height: float
    dummy: bool
    node: Node | None = None
    label: Edge | None = None
    up: list[int] = field(default_factory=list)  # neighbours in the rank above
    down: list[int] = field(default_factory=list)


@dataclass
class _Chain:
    edge: Edge
    vertices: list[int]  # top to bottom
    reversed: bool  # drawn against the layering: the real source is at the bottom


def find_back_edges(graph: Graph, start: str | None) -> set[int]:
    """Indices of the edges that close a cycle in a depth-first search from `start`."""
    out: dict[str, list[int]] = {n.id: [] for n in graph.nodes}
    for i, edge in enumerate(graph.edges):
        out[edge.source].append(i)
    roots = ([start] if start in out else []) + [n.id for n in graph.nodes]
    state: dict[str, int] = {}  # 1 on the stack, 2 finished
    back: set[int] = set()
    for root in roots:
        if root in state:
            continue
        state[root] = 1
        stack = [(root, iter(out[root]))]
        while stack:
            name, pending = stack[-1]
            for i in pending:
                target = graph.edges[i].target
                if state.get(target) == 1:
                    back.add(i)
                elif target not in state:
                    state[target] = 1
                    stack.append((target, iter(out[target])))
                    break
            else:
                state[name] = 2
                stack.pop()
    return back


def longest_path_layers(graph: Graph, back: set[int]) -> dict[str, int]:
    """Each state one layer below its lowest predecessor, back edges turned around."""
    preds: dict[str, list[str]] = {n.id: [] for n in graph.nodes}
    succs: dict[str, list[str]] = {n.id: [] for n in graph.nodes}
    for i, edge in enumerate(graph.edges):
        if edge.source == edge.target:
            continue
        upper, lower = (edge.target, edge.source) if i in back else (edge.source, edge.target)
        preds[lower].append(upper)
        succs[upper].append(lower)
    waiting = {name: len(p) for name, p in preds.items()}
    layer = {name: 0 for name in preds}
    ready = [n.id for n in graph.nodes if waiting[n.id] == 0]
    while ready:  # Kahn's order: every predecessor is final before its successors
        name = ready.pop()
        for nxt in succs[name]:
            layer[nxt] = max(layer[nxt], layer[name] + 1)
            waiting[nxt] -= 1
            if waiting[nxt] == 0:
                ready.append(nxt)
    return layer


class _Builder:
    def __init__(self, graph: Graph, metrics: Metrics) -> None:
        self.graph = graph
        self.metrics = metrics
        self.vertices: list[_Vertex] = []
        self.chains: list[_Chain] = []
        self.loops: dict[str, list[Edge]] = {}
        self.index: dict[str, int] = {}

    # -- structure --------------------------------------------------------------------------

    def build(self) -> None:
        initial = next((n.id for n in self.graph.nodes if n.initial), None)
        back = find_back_edges(self.graph, initial)
        layers = longest_path_layers(self.graph, back)
        for edge in self.graph.edges:
            if edge.source == edge.target:
                self.loops.setdefault(edge.source, []).append(edge)
        m = self.metrics
        for node in self.graph.nodes:
            width, height = m.text_size(node.lines)
            width, height = width + 2 * m.pad_x, height + 2 * m.pad_y
            right = width / 2
            loops = self.loops.get(node.id, [])
            if loops:
                label_w, label_h = m.text_size(tuple(line for e in loops for line in e.lines))
                right += LOOP_REACH + LOOP_STEP * (len(loops) - 1) + LABEL_OFFSET + label_w
                height = max(height, label_h)
            self.index[node.id] = len(self.vertices)
            self.vertices.append(_Vertex(2 * layers[node.id], width / 2, right, height, False, node))
        for i, edge in enumerate(self.graph.edges):
            if edge.source != edge.target:
                self._chain(edge, i in back)
        for vertex in self.vertices[:len(self.graph.nodes)]:
            self._widen_for_arrows(vertex)

    def _widen_for_arrows(self, vertex: _Vertex) -> None:
        """A state many arrows meet (the failure state) gets room for all their heads."""
        wanted = PORT_SPACING * (max(len(vertex.up), len(vertex.down)) + 1) / 0.8
        if wanted > 2 * vertex.left:
            vertex.right += wanted / 2 - vertex.left
            vertex.left = wanted / 2

    def _chain(self, edge: Edge, reversed_: bool) -> None:
        upper, lower = self.index[edge.target], self.index[edge.source]
        if not reversed_:
            upper, lower = lower, upper
        top, bottom = self.vertices[upper].rank, self.vertices[lower].rank
        label_rank = bottom - 1 if reversed_ else top + 1  # the label sits near the real source
        chain = [upper]
        for rank in range(top + 1, bottom):
            vertex = _Vertex(rank, DUMMY_GAP / 2, DUMMY_GAP / 2, 0.0, True)
            if rank == label_rank:
                width, height = self.metrics.text_size(edge.lines)
                vertex.right, vertex.height, vertex.label = LABEL_OFFSET + width, height, edge
            chain.append(len(self.vertices))
            self.vertices.append(vertex)
        chain.append(lower)
        for a, b in zip(chain, chain[1:]):
            self.vertices[a].down.append(b)
            self.vertices[b].up.append(a)
        self.chains.append(_Chain(edge, chain, reversed_))

    # -- ordering ---------------------------------------------------------------------------

    def ranks(self) -> list[list[int]]:
        count = max((v.rank for v in self.vertices), default=0) + 1
        ranks: list[list[int]] = [[] for _ in range(count)]
        for i in self._discovery_order():
            ranks[self.vertices[i].rank].append(i)
        return ranks

    def _discovery_order(self) -> list[int]:
        """Breadth-first from the top, children in edge order: a reasonable first ordering."""
        seen: set[int] = set()
        order: list[int] = []
        starts = sorted(range(len(self.vertices)), key=lambda i: (self.vertices[i].rank, i))
        for start in starts:
            if start in seen:
                continue
            seen.add(start)
            queue = deque([start])
            while queue:
                i = queue.popleft()
                order.append(i)
                for j in self.vertices[i].down:
                    if j not in seen:
                        seen.add(j)
                        queue.append(j)
        return order

    def order(self, ranks: list[list[int]]) -> list[list[int]]:
        best, best_crossings = [list(r) for r in ranks], self.crossings(ranks)
        for sweep in range(SWEEPS):
            downward = sweep % 2 == 0
            sequence = range(1, len(ranks)) if downward else range(len(ranks) - 2, -1, -1)
            for r in sequence:
                fixed = ranks[r - 1] if downward else ranks[r + 1]
                position = {v: k for k, v in enumerate(fixed)}
                ranks[r] = self._by_barycentre(ranks[r], position, downward)
            crossings = self.crossings(ranks)
            if crossings < best_crossings:
                best, best_crossings = [list(r) for r in ranks], crossings
        return best

    def _by_barycentre(self, rank: list[int], position: dict[int, int], downward: bool) -> list[int]:
        keys = {}
        for k, v in enumerate(rank):
            neighbours = self.vertices[v].up if downward else self.vertices[v].down
            keys[v] = sum(position[n] for n in neighbours) / len(neighbours) if neighbours else float(k)
        return sorted(rank, key=lambda v: keys[v])  # stable: ties keep their order

    def crossings(self, ranks: list[list[int]]) -> int:
        total = 0
        for upper, lower in zip(ranks, ranks[1:]):
            below = {v: k for k, v in enumerate(lower)}
            ends = sorted((k, below[d]) for k, v in enumerate(upper) for d in self.vertices[v].down)
            total += _inversions([e for _, e in ends], len(lower))
        return total

    # -- coordinates ------------------------------------------------------------------------

    def place_x(self, ranks: list[list[int]]) -> list[float]:
        x = [0.0] * len(self.vertices)
        for rank in ranks:
            offsets = self._offsets(rank)
            for v, o in zip(rank, offsets):
                x[v] = o
        for p in range(PLACEMENT_PASSES):
            downward = p % 2 == 0
            sequence = ranks[1:] if downward else ranks[-2::-1]
            for rank in sequence:
                self._pull(rank, x, lambda v: self.vertices[v].up if downward else self.vertices[v].down)
        for rank in ranks:  # settle between both neighbours
            self._pull(rank, x, lambda v: self.vertices[v].up + self.vertices[v].down)
        return x

    def _offsets(self, rank: list[int]) -> list[float]:
        """Where each vertex of a rank sits when packed as tightly as allowed, the first at 0."""
        offsets = [0.0]
        for a, b in zip(rank, rank[1:]):
            va, vb = self.vertices[a], self.vertices[b]
            gap = DUMMY_GAP if va.dummy and vb.dummy else NODE_GAP
            offsets.append(offsets[-1] + va.right + vb.left + gap)
        return offsets

    def _pull(self, rank: list[int], x: list[float], neighbours: Callable[[int], list[int]]) -> None:
        """Move a rank towards where its neighbours are, keeping its order and minimum spacing."""
        offsets = self._offsets(rank)
        targets, weights = [], []
        for v in rank:
            near = neighbours(v)
            wanted = sum(x[n] for n in near) / len(near) if near else x[v]
            targets.append(wanted)
            weights.append(2.0 if self.vertices[v].dummy else 1.0)  # keep long arrows straight
        placed = _isotonic([t - o for t, o in zip(targets, offsets)], weights)
        for v, y, o in zip(rank, placed, offsets):
            x[v] = y + o


def _inversions(values: list[int], size: int) -> int:
    """Pairs out of order, with a Fenwick tree: the crossings between two ranks."""
    tree = [0] * (size + 1)
    count = 0
    for seen, value in enumerate(values):
        i, not_greater = value + 1, 0
        while i > 0:
            not_greater += tree[i]
            i -= i & -i
        count += seen - not_greater
        i = value + 1
        while i <= size:
            tree[i] += 1
            i += i & -i
    return count


def _isotonic(targets: list[float], weights: list[float]) -> list[float]:
    """The non-decreasing sequence closest to `targets` in weighted least squares."""
    blocks: list[list[float]] = []  # [mean, weight, count]
    for t, w in zip(targets, weights):
        blocks.append([t, w, 1])
        while len(blocks) > 1 and blocks[-2][0] > blocks[-1][0]:
            m2, w2, c2 = blocks.pop()
            m1, w1, c1 = blocks[-1]
            blocks[-1] = [(m1 * w1 + m2 * w2) / (w1 + w2), w1 + w2, c1 + c2]
    return [mean for mean, _, count in blocks for _ in range(int(count))]


def layout(graph: Graph, metrics: Metrics) -> Layout:
    """Boxes and arrow routes for `graph`, in layout units, top-left origin."""
    b = _Builder(graph, metrics)
    b.build()
    ranks = b.order(b.ranks())
    x = b.place_x(ranks)
    verts = b.vertices
    shift = MARGIN - min((x[v] - verts[v].left for v in range(len(verts))), default=0.0)
    x = [value + shift for value in x]

    title_h = metrics.line_height + MARGIN
    tops, y = [], MARGIN + title_h
    for rank in ranks:
        height = max((verts[v].height for v in rank), default=0.0)
        tops.append((y, y + height))
        y += height + RANK_GAP
    width = max([x[v] + verts[v].right for v in range(len(verts))] + [metrics.text_size((graph.title,))[0]])
    result = Layout(width + MARGIN, y - RANK_GAP + MARGIN, graph.title, (MARGIN, MARGIN))

    for v, vertex in enumerate(verts):
        if vertex.node is not None:
            top, bottom = tops[vertex.rank]
            box_w, box_h = 2 * vertex.left, _box_height(vertex.node, metrics)
            centre_y = (top + bottom) / 2
            result.boxes[vertex.node.id] = Box(vertex.node, x[v] - box_w / 2, centre_y - box_h / 2, box_w, box_h)
    ports = _ports(b, x, result.boxes)
    for chain in b.chains:
        result.routes.append(_route(chain, b, x, tops, ports, result.boxes))
    for name, loops in b.loops.items():
        result.routes += _self_loops(result.boxes[name], loops, metrics)
    return result


def _box_height(node: Node, metrics: Metrics) -> float:
    return metrics.text_size(node.lines)[1] + 2 * metrics.pad_y


def _ports(b: _Builder, x: list[float], boxes: dict[str, Box]) -> dict[tuple[int, int], float]:
    """Where each arrow meets a box: spread along its top or bottom side in the order of the
    arrows' other ends, so arrows into a busy state (the failure state) do not pile up."""
    ports: dict[tuple[int, int], float] = {}
    for v, vertex in enumerate(b.vertices):
        if vertex.node is None:
            continue
        box = boxes[vertex.node.id]
        for side in (vertex.up, vertex.down):
            ordered = sorted(side, key=lambda n: (x[n], n))
            usable = box.width * 0.8
            for k, n in enumerate(ordered):
                ports[(v, n)] = box.x + box.width * 0.1 + usable * (k + 1) / (len(ordered) + 1)
    return ports


def _route(chain: _Chain, b: _Builder, x: list[float], tops: list[tuple[float, float]],
           ports: dict[tuple[int, int], float], boxes: dict[str, Box]) -> Route:
    """Down from the upper box, straight through each rank it crosses, into the lower box."""
    verts = b.vertices
    first, second, last, before_last = chain.vertices[0], chain.vertices[1], chain.vertices[-1], chain.vertices[-2]
    upper_box, lower_box = boxes[chain.edge.target if chain.reversed else chain.edge.source], \
        boxes[chain.edge.source if chain.reversed else chain.edge.target]
    points: list[Point] = [(ports[(first, second)], upper_box.bottom)]
    label_at: Point = (0.0, 0.0)
    for v in chain.vertices[1:-1]:
        top, bottom = tops[verts[v].rank]
        points += [(x[v], top), (x[v], bottom)]
        if verts[v].label is not None:
            _, height = b.metrics.text_size(chain.edge.lines)
            label_at = (x[v] + LABEL_OFFSET, (top + bottom) / 2 - height / 2)
    points.append((ports[(last, before_last)], lower_box.y))
    if chain.reversed:
        points.reverse()
    return Route(chain.edge, tuple(points), False, label_at)


def _self_loops(box: Box, loops: list[Edge], metrics: Metrics) -> list[Route]:
    """Nested loops on the right side of the box, labels stacked beside the outermost."""
    routes = []
    cy = box.y + box.height / 2
    label_x = box.right + LOOP_REACH + LOOP_STEP * (len(loops) - 1) + LABEL_OFFSET
    label_y = cy - metrics.text_size(tuple(line for e in loops for line in e.lines))[1] / 2
    for k, edge in enumerate(loops):
        reach = LOOP_REACH + LOOP_STEP * k
        rise = min(box.height / 2 - 2, 6 + 4 * k)
        start, end = (box.right, cy - rise), (box.right, cy + rise)
        bulge = rise + 8 + 4 * k
        points = (start, (box.right + reach * 1.33, cy - bulge), (box.right + reach * 1.33, cy + bulge), end)
        routes.append(Route(edge, points, True, (label_x, label_y)))
        label_y += metrics.text_size(edge.lines)[1]
    return routes
