"""Pick the renderer for an output format: graphviz when asked for or present, else the library layout."""

from __future__ import annotations

from enum import StrEnum

from atd.graph.dot import GraphvizError, graphviz_available, render_with_graphviz, to_dot
from atd.graph.layout import layout
from atd.graph.model import Graph
from atd.graph.png import to_png
from atd.graph.svg import to_svg

FORMATS = ("dot", "svg", "png")
LIBRARY_LAYOUT = "the library layout (grandalf)"


class Renderer(StrEnum):
    AUTO = "auto"  # graphviz when `dot` is on PATH, else the library layout
    GRAPHVIZ = "graphviz"
    BUILTIN = "builtin"  # the library layout: grandalf places, resvg rasterises; no program needed


def render(graph: Graph, fmt: str, renderer: Renderer = Renderer.AUTO) -> tuple[bytes, str]:
    """The picture's bytes and what drew it (for the user's message).

    With AUTO, a `dot` that fails is reported through GraphvizError only when there is no
    fallback; otherwise the library layout draws the picture and the reason is returned.
    """
    dot_text = to_dot(graph)
    if fmt == "dot":
        return dot_text.encode(), "DOT text"
    if renderer is Renderer.GRAPHVIZ or (renderer is Renderer.AUTO and graphviz_available()):
        try:
            return render_with_graphviz(dot_text, fmt), "graphviz"
        except GraphvizError as exc:
            if renderer is Renderer.GRAPHVIZ:
                raise
            fallback = f"{LIBRARY_LAYOUT} ({exc})"
    else:
        fallback = LIBRARY_LAYOUT
    drawing = layout(graph)
    return (to_svg(drawing) if fmt == "svg" else to_png(drawing)), fallback
