"""Drawing tasks: an ATD or an ESTD as a picture (DOT, SVG, PNG), with or without graphviz."""
