"""Curves and arrowheads shared by the SVG and PNG writers, so both draw the same picture."""

from __future__ import annotations

import math

from atd.graph.layout import Point, Route

Cubic = tuple[Point, Point, Point, Point]

ARROW_LENGTH = 9.0
ARROW_HALF_WIDTH = 4.0


def route_pieces(route: Route) -> list[Cubic]:
    """The cubic Bezier pieces of a route.

    A self-loop is one cubic. Otherwise each step between two route points is an S-curve
    that leaves and arrives vertically: straight when the points line up, smooth where an
    arrow shifts sideways between ranks.
    """
    if route.loop:
        a, b, c, d = route.points
        return [(a, b, c, d)]
    points = [p for k, p in enumerate(route.points) if k == 0 or p != route.points[k - 1]]
    pieces = []
    for (x0, y0), (x1, y1) in zip(points, points[1:]):
        half = (y1 - y0) / 2
        pieces.append(((x0, y0), (x0, y0 + half), (x1, y1 - half), (x1, y1)))
    return pieces


def arrowhead(piece: Cubic) -> tuple[Point, Point, Point]:
    """Tip and the two back corners of the arrowhead at the end of the last piece."""
    tip = piece[3]
    towards = next((p for p in (piece[2], piece[1], piece[0]) if p != tip), (tip[0], tip[1] - 1))
    dx, dy = tip[0] - towards[0], tip[1] - towards[1]
    length = math.hypot(dx, dy)
    ux, uy = dx / length, dy / length
    bx, by = tip[0] - ux * ARROW_LENGTH, tip[1] - uy * ARROW_LENGTH
    return tip, (bx - uy * ARROW_HALF_WIDTH, by + ux * ARROW_HALF_WIDTH), (bx + uy * ARROW_HALF_WIDTH, by - ux * ARROW_HALF_WIDTH)


def sample(piece: Cubic, steps: int) -> list[Point]:
    """Points along a cubic, both ends included, for drawing it with straight lines."""
    (x0, y0), (x1, y1), (x2, y2), (x3, y3) = piece
    out = []
    for k in range(steps + 1):
        t = k / steps
        s = 1 - t
        a, b, c, d = s * s * s, 3 * s * s * t, 3 * s * t * t, t * t * t
        out.append((a * x0 + b * x1 + c * x2 + d * x3, a * y0 + b * y1 + c * y2 + d * y3))
    return out
