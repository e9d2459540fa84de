"""SVG from the library layout: boxes, curved arrows with their labels, all text in the one font."""

from __future__ import annotations

from xml.sax.saxutils import escape, quoteattr

from atd.graph import text
from atd.graph.layout import LABEL_PAD, MARGIN, PAD_Y, Layout, Route
from atd.graph.model import NodeKind, Trail
from atd.graph.style import BACKGROUND, EDGE_COLOUR, FADED_BORDER, TEXT_COLOUR, edge_look, node_colours

FONT = f"{text.FAMILY}, Menlo, Consolas, monospace"


def _n(value: float) -> str:
    return f"{value:.1f}"


def _text(lines: tuple[str, ...], x: float, top: float, anchor: str, colour: str, bold_first: bool = False) -> str:
    """One <text> per line, baselines a line apart."""
    out = []
    for k, line in enumerate(lines):
        weight = ' font-weight="bold"' if bold_first and k == 0 else ""
        out.append(f'<text x="{_n(x)}" y="{_n(top + k * text.LINE_HEIGHT + text.ASCENT)}" text-anchor="{anchor}" '
                   f'fill="{colour}"{weight} xml:space="preserve">{escape(line)}</text>')
    return "".join(out)


def _path(route: Route) -> str:
    """A self-loop is its one cubic; any other arrow is an S-curve from each point to the next,
    leaving and arriving vertically, so it is straight where the points line up."""
    (x0, y0), *rest = route.points
    if route.loop:
        return f"M{_n(x0)},{_n(y0)} C" + " ".join(f"{_n(x)},{_n(y)}" for x, y in rest)
    steps = []
    for (xa, ya), (xb, yb) in zip(route.points, rest):
        middle = (ya + yb) / 2
        steps.append(f" C{_n(xa)},{_n(middle)} {_n(xb)},{_n(middle)} {_n(xb)},{_n(yb)}")
    return f"M{_n(x0)},{_n(y0)}" + "".join(steps)


def _marker(name: str, colour: str) -> str:
    return (f'<marker id="{name}" viewBox="0 0 10 8" refX="10" refY="4" markerWidth="9" markerHeight="7.2" '
            f'markerUnits="userSpaceOnUse" orient="auto"><path d="M0,0 L10,4 L0,8 z" fill="{colour}"/></marker>')


def _route(route: Route) -> str:
    label, edge = route.label, route.edge
    colour, width, ink = edge_look(edge)
    head = "arrowhead-faded" if edge.trail is Trail.FADED else "arrowhead"
    return (f'<g class="edge" data-transition={quoteattr(edge.id)} data-trail="{edge.trail.value}">'
            f'<title>{escape(edge.id)}</title>'
            f'<path d="{_path(route)}" fill="none" stroke="{colour}" stroke-width="{width:g}" '
            f'marker-end="url(#{head})"/>'
            f'<rect x="{_n(label.x)}" y="{_n(label.y)}" width="{_n(label.width)}" height="{_n(label.height)}" '
            f'rx="3" fill="{BACKGROUND}"/>'
            f'{_text(edge.lines, label.x + LABEL_PAD, label.y + LABEL_PAD, "start", ink)}</g>')


def to_svg(drawing: Layout) -> bytes:
    parts = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{drawing.width}" height="{drawing.height}" '
        f'viewBox="0 0 {drawing.width} {drawing.height}" font-family="{FONT}" font-size="{text.SIZE:g}">',
        f'<defs>{_marker("arrowhead", EDGE_COLOUR)}{_marker("arrowhead-faded", FADED_BORDER)}</defs>',
        f'<rect width="100%" height="100%" fill="{BACKGROUND}"/>',
        _text((drawing.title,), MARGIN, MARGIN, "start", TEXT_COLOUR, bold_first=True),
    ]
    parts += [_route(route) for route in drawing.routes]
    for box in drawing.boxes.values():
        fill, border, ink = node_colours(box.node)
        width = 2.5 if box.node.initial else 1.2
        parts.append(f'<g class="state" data-state={quoteattr(box.node.id)} data-trail="{box.node.trail.value}">')
        parts.append(f'<rect x="{_n(box.x)}" y="{_n(box.y)}" width="{_n(box.width)}" height="{_n(box.height)}" '
                     f'rx="6" fill="{fill}" stroke="{border}" stroke-width="{width}"/>')
        if box.node.kind in (NodeKind.SUCCESS, NodeKind.FAILURE):
            parts.append(f'<rect x="{_n(box.x + 3)}" y="{_n(box.y + 3)}" width="{_n(box.width - 6)}" '
                         f'height="{_n(box.height - 6)}" rx="4" fill="none" stroke="{border}" stroke-width="1"/>')
        parts.append(_text(box.node.lines, box.x + box.width / 2, box.y + PAD_Y, "middle", ink, bold_first=True))
        parts.append("</g>")
    parts.append("</svg>")
    return ("\n".join(parts) + "\n").encode()
