"""Pick the renderer for an output format: graphviz when asked for or present, else the built-in one."""

from __future__ import annotations

from enum import StrEnum

from atd.graph.dot import GraphvizError, graphviz_available, render_with_graphviz, to_dot
from atd.graph.layout import layout
from atd.graph.model import Graph
from atd.graph.png import PNG_METRICS, to_png
from atd.graph.svg import SVG_METRICS, to_svg

FORMATS = ("dot", "svg", "png")


class Renderer(StrEnum):
    AUTO = "auto"  # graphviz when `dot` is on PATH, else built-in
    GRAPHVIZ = "graphviz"
    BUILTIN = "builtin"


def render(graph: Graph, fmt: str, renderer: Renderer = Renderer.AUTO) -> tuple[bytes, str]:
    """The picture's bytes and what drew it (for the user's message).

    With AUTO, a `dot` that fails is reported through GraphvizError only when there is no
    fallback; otherwise the built-in layout draws the picture and the reason is returned.
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
            fallback = f"the built-in layout ({exc})"
    else:
        fallback = "the built-in layout"
    if fmt == "svg":
        return to_svg(layout(graph, SVG_METRICS)), fallback
    return to_png(layout(graph, PNG_METRICS)), fallback
