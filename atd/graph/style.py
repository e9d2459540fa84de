"""The look shared by every renderer, so a graphviz picture and a library-layout one read the same way."""

from atd.graph.model import Edge, Node, NodeKind, Trail

# kind -> (fill, border)
PALETTE: dict[NodeKind, tuple[str, str]] = {
    NodeKind.PRIMITIVE: ("#e8f0fe", "#2b4a80"),
    NodeKind.SUBTASK: ("#fff4d6", "#8a6500"),
    NodeKind.SUCCESS: ("#dff3e0", "#1e7a2e"),
    NodeKind.FAILURE: ("#fbe3e1", "#b02a1e"),
}
# A state the run never visited, a transition it never took: grey, so the path taken stands out.
FADED_FILL, FADED_BORDER, FADED_TEXT = "#f4f4f4", "#c4c4c4", "#9a9a9a"
EDGE_COLOUR = "#444444"
EDGE_WIDTH = 1.2
TAKEN_WIDTH = 3.0  # a transition the run took: thicker than the rest
TEXT_COLOUR = "#111111"
LABEL_COLOUR = "#333333"
BACKGROUND = "#ffffff"


def node_colours(node: Node) -> tuple[str, str, str]:
    """Fill, border and text colour of a box."""
    if node.trail is Trail.FADED:
        return FADED_FILL, FADED_BORDER, FADED_TEXT
    return (*PALETTE[node.kind], TEXT_COLOUR)


def edge_look(edge: Edge) -> tuple[str, float, str]:
    """Colour, width and label colour of an arrow."""
    if edge.trail is Trail.FADED:
        return FADED_BORDER, EDGE_WIDTH, FADED_TEXT
    return EDGE_COLOUR, TAKEN_WIDTH if edge.trail is Trail.TAKEN else EDGE_WIDTH, LABEL_COLOUR
