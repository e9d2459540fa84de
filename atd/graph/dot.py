"""Graphviz: the DOT text of a graph, and pictures from the `dot` program when it is installed.

The DOT is written in document order with fixed attributes, so the same graph always gives
the same bytes (diffable, cacheable).
"""

from __future__ import annotations

import shutil
import subprocess

from atd.graph.model import Graph, NodeKind, Trail
from atd.graph.style import edge_look, node_colours  # the same colours as the library layout

DOT_TIMEOUT_S = 60


class GraphvizError(RuntimeError):
    """`dot` is missing or failed; the message says which and what to do."""


def _quote(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def _label(lines: tuple[str, ...]) -> str:
    return _quote("\n".join(lines)).replace("\n", "\\n")


def to_dot(graph: Graph) -> str:
    out = [
        "digraph task {",
        f"  label={_quote(graph.title)};",
        "  labelloc=t;",
        '  fontname="Helvetica";',
        "  rankdir=TB;",
        '  node [shape=box, style="rounded,filled", fontname="Helvetica", fontsize=11];',
        '  edge [fontname="Helvetica", fontsize=10, color="#444444"];',
    ]
    for node in graph.nodes:
        fill, border, ink = node_colours(node)
        attrs = [f"label={_label(node.lines)}", f'fillcolor="{fill}"', f'color="{border}"']
        if node.trail is Trail.FADED:
            attrs.append(f'fontcolor="{ink}"')
        if node.kind in (NodeKind.SUCCESS, NodeKind.FAILURE):
            attrs.append("peripheries=2")
        if node.initial:
            attrs.append("penwidth=2.5")
        out.append(f"  {_quote(node.id)} [{', '.join(attrs)}];")
    for edge in graph.edges:
        colour, width, ink = edge_look(edge)
        look = "" if edge.trail is Trail.PLAIN else f', color="{colour}", fontcolor="{ink}", penwidth={width:g}'
        out.append(f"  {_quote(edge.source)} -> {_quote(edge.target)} [label={_label(edge.lines)}, "
                   f"tooltip={_quote(edge.id)}{look}];")
    out.append("}")
    return "\n".join(out) + "\n"


def graphviz_available() -> bool:
    return shutil.which("dot") is not None


def render_with_graphviz(dot_text: str, fmt: str) -> bytes:
    """`dot -T<fmt>` on the DOT text; raises GraphvizError with the program's own complaint."""
    program = shutil.which("dot")
    if program is None:
        raise GraphvizError("graphviz is not installed (no 'dot' on PATH)")
    try:
        done = subprocess.run([program, f"-T{fmt}"], input=dot_text.encode(), capture_output=True,
                              timeout=DOT_TIMEOUT_S, check=False)
    except (OSError, subprocess.TimeoutExpired) as exc:
        raise GraphvizError(f"could not run {program}: {exc}") from None
    if done.returncode != 0 or not done.stdout:
        reason = done.stderr.decode(errors="replace").strip() or f"exit status {done.returncode}"
        raise GraphvizError(f"{program} -T{fmt} failed: {reason}")
    return done.stdout
