"""SVG from the built-in layout, with the standard library only (no graphviz)."""

from __future__ import annotations

from xml.sax.saxutils import escape, quoteattr

from atd.graph.geometry import arrowhead, route_pieces
from atd.graph.layout import Layout, Metrics, Route
from atd.graph.model import NodeKind
from atd.graph.style import BACKGROUND, EDGE_COLOUR, LABEL_COLOUR, PALETTE, TEXT_COLOUR

FONT_SIZE = 12.0
# Monospace glyphs are 0.6 em wide in the common fonts (DejaVu Sans Mono, Menlo, Consolas).
SVG_METRICS = Metrics(char_width=FONT_SIZE * 0.6, line_height=FONT_SIZE * 1.3)
FONT = "DejaVu Sans Mono, Menlo, Consolas, monospace"


def _n(value: float) -> str:
    return f"{value:.1f}"


def _text(lines: tuple[str, ...], x: float, top: float, anchor: str, colour: str, bold_first: bool = False) -> str:
    """One <text> per line, baselines a line apart."""
    out = []
    for k, line in enumerate(lines):
        baseline = top + SVG_METRICS.line_height * (k + 0.78)
        weight = ' font-weight="bold"' if bold_first and k == 0 else ""
        out.append(f'<text x="{_n(x)}" y="{_n(baseline)}" text-anchor="{anchor}" fill="{colour}"{weight} '
                   f'xml:space="preserve">{escape(line)}</text>')
    return "".join(out)


def _route(route: Route) -> str:
    pieces = route_pieces(route)
    start = pieces[0][0]
    path = f"M{_n(start[0])},{_n(start[1])}" + "".join(
        f" C{_n(c1[0])},{_n(c1[1])} {_n(c2[0])},{_n(c2[1])} {_n(p[0])},{_n(p[1])}" for _, c1, c2, p in pieces)
    head = " ".join(f"{_n(px)},{_n(py)}" for px, py in arrowhead(pieces[-1]))
    return (f'<g class="edge" data-transition={quoteattr(route.edge.id)}>'
            f'<title>{escape(route.edge.id)}</title>'
            f'<path d="{path}" fill="none" stroke="{EDGE_COLOUR}" stroke-width="1.2"/>'
            f'<polygon points="{head}" fill="{EDGE_COLOUR}"/>'
            f'{_text(route.edge.lines, route.label_at[0], route.label_at[1], "start", LABEL_COLOUR)}</g>')


def to_svg(drawing: Layout) -> bytes:
    parts = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{_n(drawing.width)}" height="{_n(drawing.height)}" '
        f'viewBox="0 0 {_n(drawing.width)} {_n(drawing.height)}" font-family="{FONT}" font-size="{FONT_SIZE:g}">',
        f'<rect width="100%" height="100%" fill="{BACKGROUND}"/>',
        _text((drawing.title,), drawing.title_at[0], drawing.title_at[1], "start", TEXT_COLOUR, bold_first=True),
    ]
    for route in drawing.routes:
        parts.append(_route(route))
    for box in drawing.boxes.values():
        fill, border = PALETTE[box.node.kind]
        width = 2.5 if box.node.initial else 1.2
        parts.append(f'<g class="state" data-state={quoteattr(box.node.id)}>')
        parts.append(f'<rect x="{_n(box.x)}" y="{_n(box.y)}" width="{_n(box.width)}" height="{_n(box.height)}" '
                     f'rx="6" fill="{fill}" stroke="{border}" stroke-width="{width}"/>')
        if box.node.kind in (NodeKind.SUCCESS, NodeKind.FAILURE):
            parts.append(f'<rect x="{_n(box.x + 3)}" y="{_n(box.y + 3)}" width="{_n(box.width - 6)}" '
                         f'height="{_n(box.height - 6)}" rx="4" fill="none" stroke="{border}" stroke-width="1"/>')
        parts.append(_text(box.node.lines, box.x + box.width / 2, box.y + SVG_METRICS.pad_y, "middle",
                           TEXT_COLOUR, bold_first=True))
        parts.append("</g>")
    parts.append("</svg>")
    return ("\n".join(parts) + "\n").encode()
