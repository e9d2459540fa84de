"""PNG from the library layout: its SVG rasterised by resvg, with the font the layout measured."""

from __future__ import annotations

import resvg_py

from atd.graph import text
from atd.graph.layout import Layout, PictureTooBig
from atd.graph.style import BACKGROUND
from atd.graph.svg import to_svg

SCALE = 2  # pixels per layout unit, so 12 px text stays sharp on a high-density screen
MAX_PIXELS = 40_000_000  # resvg holds 4 bytes a pixel: ~160 MB; beyond that SVG is the better format


def to_png(drawing: Layout) -> bytes:
    """The drawing at double size, or at natural size when doubling would pass MAX_PIXELS."""
    width, height = drawing.width, drawing.height
    if width * height > MAX_PIXELS:
        raise PictureTooBig(f"the drawing would be {width} x {height} pixels, too big for a PNG; "
                            "draw it as .svg (any size) or .dot instead")
    scale = SCALE if width * height * SCALE * SCALE <= MAX_PIXELS else 1
    return resvg_py.svg_to_bytes(svg_string=to_svg(drawing).decode(), zoom=scale, background=BACKGROUND,
                                 skip_system_fonts=True, font_files=list(text.FILES), font_family=text.FAMILY,
                                 monospace_family=text.FAMILY)
