"""The look shared by every renderer, so a graphviz picture and a library-layout one read the same way."""

from atd.graph.model import NodeKind

# kind -> (fill, border)
PALETTE: dict[NodeKind, tuple[str, str]] = {
    NodeKind.PRIMITIVE: ("#e8f0fe", "#2b4a80"),
    NodeKind.SUBTASK: ("#fff4d6", "#8a6500"),
    NodeKind.SUCCESS: ("#dff3e0", "#1e7a2e"),
    NodeKind.FAILURE: ("#fbe3e1", "#b02a1e"),
}
EDGE_COLOUR = "#444444"
TEXT_COLOUR = "#111111"
LABEL_COLOUR = "#333333"
BACKGROUND = "#ffffff"
