"""The one font every picture is drawn and measured in: DejaVu Sans Mono, as matplotlib ships it.

Boxes are sized from the font's own advance width, and the PNG rasteriser is given the same
files, so text fits its box on any machine, with or without system fonts. A monospaced font
also keeps the indented controller parameters of an ESTD box lined up.
"""

from __future__ import annotations

from functools import cache
from pathlib import Path

import matplotlib
from matplotlib.ft2font import FT2Font

FAMILY = "DejaVu Sans Mono"
FILES = tuple(str(Path(matplotlib.get_data_path()) / "fonts" / "ttf" / name)
              for name in ("DejaVuSansMono.ttf", "DejaVuSansMono-Bold.ttf"))
SIZE = 12.0  # pixels
LINE_HEIGHT = SIZE * 1.3
ASCENT = SIZE * 0.95  # from a line's top to its baseline


@cache
def char_width() -> float:
    """The advance of every character (bold too) at SIZE pixels, read from the font file."""
    font = FT2Font(FILES[0])
    font.set_size(SIZE, 72)  # 72 dpi: points are pixels
    return font.load_char(ord("M")).linearHoriAdvance / 65536


def text_size(lines: tuple[str, ...]) -> tuple[float, float]:
    """Width and height of a block of lines, in pixels."""
    return max((len(line) for line in lines), default=0) * char_width(), len(lines) * LINE_HEIGHT
