"""PNG from the built-in layout: boxes, curves and the bitmap font on a `Canvas`."""

from __future__ import annotations

import math

from atd.graph.font import GLYPH_HEIGHT, GLYPH_WIDTH
from atd.graph.geometry import arrowhead, route_pieces, sample
from atd.graph.layout import Layout, Metrics, Route
from atd.graph.model import NodeKind
from atd.graph.raster import Canvas, colour
from atd.graph.style import BACKGROUND, EDGE_COLOUR, LABEL_COLOUR, PALETTE, TEXT_COLOUR

SCALE = 2  # every layout pixel drawn as 2x2, so the 5x9 glyphs read like a 10x18 font
MAX_PIXELS = 40_000_000  # ~120 MB of RGB while drawing; beyond that SVG is the better format


class PictureTooBig(ValueError):
    """The task is too big to draw as a bitmap; the message suggests SVG."""
PNG_METRICS = Metrics(char_width=GLYPH_WIDTH + 1, line_height=GLYPH_HEIGHT + 2, pad_x=6.0, pad_y=4.0)


def _text_block(canvas: Canvas, lines: tuple[str, ...], x: float, top: float, ink: bytes, centred_in: float | None,
                bold_first: bool = False) -> None:
    advance, line_height = int(PNG_METRICS.char_width), PNG_METRICS.line_height
    for k, line in enumerate(lines):
        left = x if centred_in is None else x + (centred_in - len(line) * advance) / 2
        canvas.text(round(left), round(top + k * line_height + 1), line, ink, advance, bold_first and k == 0)


def _route(canvas: Canvas, route: Route) -> None:
    ink = colour(EDGE_COLOUR)
    pieces = route_pieces(route)
    for piece in pieces:
        length = math.dist(piece[0], piece[1]) + math.dist(piece[1], piece[2]) + math.dist(piece[2], piece[3])
        points = sample(piece, max(2, int(length / 4)))
        for (x0, y0), (x1, y1) in zip(points, points[1:]):
            canvas.line(round(x0), round(y0), round(x1), round(y1), ink)
    canvas.triangle(arrowhead(pieces[-1]), ink)
    _text_block(canvas, route.edge.lines, route.label_at[0], route.label_at[1], colour(LABEL_COLOUR), None)


def to_png(drawing: Layout) -> bytes:
    """The drawing at double size, or at natural size when doubling would pass MAX_PIXELS."""
    width, height = math.ceil(drawing.width), math.ceil(drawing.height)
    scale = SCALE if width * height * SCALE * SCALE <= MAX_PIXELS else 1
    if width * height > MAX_PIXELS:
        raise PictureTooBig(f"the drawing would be {width} x {height} pixels, too big for a PNG; "
                            "draw it as .svg (any size) or .dot instead")
    canvas = Canvas(width, height, colour(BACKGROUND))
    _text_block(canvas, (drawing.title,), drawing.title_at[0], drawing.title_at[1], colour(TEXT_COLOUR), None,
                bold_first=True)
    for route in drawing.routes:
        _route(canvas, route)
    for box in drawing.boxes.values():
        fill, border = (colour(c) for c in PALETTE[box.node.kind])
        x0, y0, x1, y1 = round(box.x), round(box.y), round(box.right), round(box.bottom)
        canvas.fill_rect(x0, y0, x1, y1, fill)
        canvas.frame(x0, y0, x1, y1, border, 2 if box.node.initial else 1)
        if box.node.kind in (NodeKind.SUCCESS, NodeKind.FAILURE):
            canvas.frame(x0 + 3, y0 + 3, x1 - 3, y1 - 3, border)
        _text_block(canvas, box.node.lines, box.x, box.y + PNG_METRICS.pad_y, colour(TEXT_COLOUR), box.width,
                    bold_first=True)
    return canvas.to_png(scale)
