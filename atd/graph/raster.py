"""A tiny RGB canvas and PNG encoder on the standard library (zlib + struct).

Just enough to draw a task graph when graphviz is absent: filled rectangles, lines,
filled triangles and bitmap text. No anti-aliasing; `to_png(scale=2)` doubles every pixel
so the 5x9 font stays legible.
"""

from __future__ import annotations

import struct
import zlib

from atd.graph.font import glyph

Colour = bytes  # 3 bytes: r, g, b

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def colour(hex_text: str) -> Colour:
    return bytes.fromhex(hex_text.lstrip("#"))


class Canvas:
    def __init__(self, width: int, height: int, background: Colour) -> None:
        self.width, self.height = width, height
        self.pixels = bytearray(background * (width * height))

    def dot(self, x: int, y: int, ink: Colour) -> None:
        if 0 <= x < self.width and 0 <= y < self.height:
            i = 3 * (y * self.width + x)
            self.pixels[i:i + 3] = ink

    def fill_rect(self, x0: int, y0: int, x1: int, y1: int, ink: Colour) -> None:
        """Fill the pixels with x0 <= x <= x1, y0 <= y <= y1 (clipped to the canvas)."""
        x0, x1 = max(x0, 0), min(x1, self.width - 1)
        if x0 > x1:
            return
        span = ink * (x1 - x0 + 1)
        for y in range(max(y0, 0), min(y1, self.height - 1) + 1):
            i = 3 * (y * self.width + x0)
            self.pixels[i:i + len(span)] = span

    def frame(self, x0: int, y0: int, x1: int, y1: int, ink: Colour, thickness: int = 1) -> None:
        for t in range(thickness):
            self.fill_rect(x0 + t, y0 + t, x1 - t, y0 + t, ink)
            self.fill_rect(x0 + t, y1 - t, x1 - t, y1 - t, ink)
            self.fill_rect(x0 + t, y0 + t, x0 + t, y1 - t, ink)
            self.fill_rect(x1 - t, y0 + t, x1 - t, y1 - t, ink)

    def line(self, x0: int, y0: int, x1: int, y1: int, ink: Colour) -> None:
        """Bresenham's line, both ends included."""
        dx, dy = abs(x1 - x0), -abs(y1 - y0)
        sx, sy = (1 if x0 < x1 else -1), (1 if y0 < y1 else -1)
        err = dx + dy
        while True:
            self.dot(x0, y0, ink)
            if x0 == x1 and y0 == y1:
                return
            e2 = 2 * err
            if e2 >= dy:
                err += dy
                x0 += sx
            if e2 <= dx:
                err += dx
                y0 += sy

    def triangle(self, points: tuple[tuple[float, float], ...], ink: Colour) -> None:
        """Fill a triangle row by row: each row is filled between its crossings of the sides."""
        ys = [p[1] for p in points]
        for y in range(int(min(ys)), int(max(ys)) + 1):
            centre = y + 0.5
            crossings = []
            for (ax, ay), (bx, by) in zip(points, points[1:] + points[:1]):
                if (ay <= centre < by) or (by <= centre < ay):
                    crossings.append(ax + (centre - ay) * (bx - ax) / (by - ay))
            if len(crossings) >= 2:
                self.fill_rect(round(min(crossings)), y, round(max(crossings)), y, ink)

    def text(self, x: int, top: int, line: str, ink: Colour, advance: int, bold: bool = False) -> None:
        """Draw one line of text with its cell's top-left at (x, top)."""
        for k, char in enumerate(line):
            left = x + k * advance
            for col, row in glyph(char):
                self.dot(left + col, top + row, ink)
                if bold:
                    self.dot(left + col + 1, top + row, ink)

    def to_png(self, scale: int = 1) -> bytes:
        """An 8-bit RGB PNG, every pixel repeated `scale` times each way."""
        stride = 3 * self.width
        rows = []
        for y in range(self.height):
            row = self.pixels[y * stride:(y + 1) * stride]
            if scale > 1:
                wide = bytearray(len(row) * scale)
                for copy in range(scale):
                    for channel in range(3):
                        wide[3 * copy + channel::3 * scale] = row[channel::3]
                row = wide
            rows += [b"\x00" + bytes(row)] * scale  # filter type 0 per row
        header = struct.pack(">IIBBBBB", self.width * scale, self.height * scale, 8, 2, 0, 0, 0)
        return PNG_SIGNATURE + _chunk(b"IHDR", header) + _chunk(b"IDAT", zlib.compress(b"".join(rows), 9)) \
            + _chunk(b"IEND", b"")


def _chunk(kind: bytes, data: bytes) -> bytes:
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
