"""DOT, SVG and PNG of real tasks, and the choice between graphviz and the library layout."""

from __future__ import annotations

import io
import re
import shutil
import stat
import sys

import numpy as np
import pytest
from lxml import etree

from PIL import Image, ImageColor

from atd.graph import png
from atd.graph.dot import GraphvizError, to_dot
from atd.graph.layout import Box, PictureTooBig, layout
from atd.graph.model import Node, NodeKind, from_estd
from atd.graph.render import Renderer, render
from atd.graph.style import PALETTE
from atd.model import load_task
from factories.registry import create
from tests.conftest import EXAMPLES
from tests.graph.test_layout import example_graph
from translator import translate

SVG = "{http://www.w3.org/2000/svg}"
NODE_LINE = re.compile(r'^  "([^"]+)" \[label=')
EDGE_LINE = re.compile(r'^  "([^"]+)" -> "([^"]+)" \[label="([^"]*)"')


@pytest.fixture
def no_graphviz(monkeypatch):
    """A machine without graphviz, whatever this one has."""
    monkeypatch.setattr(shutil, "which", lambda name, *a, **k: None)


def fake_dot(tmp_path, monkeypatch, script: str) -> None:
    """Put an executable `dot` on PATH that runs `script` (Python) on the DOT it is given."""
    program = tmp_path / "bin" / "dot"
    program.parent.mkdir()
    program.write_text(f"#!{sys.executable}\nimport sys\n{script}\n")  # not a shim: PATH is only bin/
    program.chmod(program.stat().st_mode | stat.S_IEXEC)
    monkeypatch.setenv("PATH", str(program.parent))


def melfa_estd():
    task, _ = load_task(EXAMPLES / "pick_and_place.xml")
    result = translate(task, create("melfa"))
    assert result.estd is not None, result.diagnostics
    return result.estd


def test_dot_has_one_node_per_state_and_one_edge_per_transition():
    task, _ = load_task(EXAMPLES / "pick_and_place.xml")
    text = to_dot(example_graph("pick_and_place.xml"))
    nodes = [m.group(1) for line in text.splitlines() if (m := NODE_LINE.match(line))]
    edges = [m.groups() for line in text.splitlines() if (m := EDGE_LINE.match(line))]
    assert nodes == [s.name for s in task.states]
    assert edges == [(t.origin, t.destination, t.label) for t in task.transitions]
    assert ("grasp", "lift", "success & grasp_stable") in edges
    assert ("approach", "failed", "timeout(20s)") in edges
    assert text == to_dot(example_graph("pick_and_place.xml"))  # deterministic


def test_dot_quotes_awkward_names():
    graph = example_graph("simple_move.xml")
    graph.nodes[0] = Node('say "hi"\\', graph.nodes[0].lines, graph.nodes[0].kind)
    assert '"say \\"hi\\"\\\\" [label=' in to_dot(graph)


def test_svg_fallback_is_wellformed_with_a_box_per_state_and_an_arrow_per_transition(no_graphviz):
    graph = example_graph("pick_and_place.xml")
    data, drawn_by = render(graph, "svg")
    assert drawn_by == "the library layout (grandalf)"
    root = etree.fromstring(data)
    assert root.tag == f"{SVG}svg"
    states = root.findall(f"{SVG}g[@class='state']")
    assert [g.get("data-state") for g in states] == [n.id for n in graph.nodes]
    for g, node in zip(states, graph.nodes):
        assert [t.text for t in g.findall(f"{SVG}text")] == list(node.lines)  # the name first, then the details
    edges = root.findall(f"{SVG}g[@class='edge']")
    assert sorted(g.get("data-transition") for g in edges) == sorted(e.id for e in graph.edges)
    for g in edges:
        assert g.find(f"{SVG}path").get("marker-end") == "url(#arrowhead)"  # every arrow has its head
    labels = {t.text for g in edges for t in g.findall(f"{SVG}text")}
    assert {"success", "success & grasp_stable", "grasp_lost", "timeout(20s)", "hardware_failure"} <= labels
    assert render(graph, "svg")[0] == data  # same task, same bytes: pictures can be diffed


def png_image(data: bytes) -> Image.Image:
    image = Image.open(io.BytesIO(data))
    image.load()  # decodes every pixel: a truncated or corrupt PNG fails here
    return image.convert("RGB")


def ink_inside(image: Image.Image, box: Box) -> int:
    """Dark pixels (text) inside a box of a PNG drawn at double size, away from the box's border."""
    inner = image.crop((round((box.x + 5) * 2), round((box.y + 5) * 2),
                        round((box.right - 5) * 2), round((box.bottom - 5) * 2)))
    return int((np.asarray(inner, dtype=int).sum(axis=2) < 200).sum())


def test_png_fallback_is_the_layout_drawn_at_double_size_with_its_text(no_graphviz):
    graph = example_graph("retry_grasp.xml")
    data, drawn_by = render(graph, "png")
    assert drawn_by == "the library layout (grandalf)"
    drawing = layout(graph)
    image = png_image(data)
    assert image.size == (2 * drawing.width, 2 * drawing.height)
    colours = {c for _, c in image.getcolors(maxcolors=1 << 20)}
    for kind in (NodeKind.PRIMITIVE, NodeKind.SUCCESS, NodeKind.FAILURE):
        assert ImageColor.getrgb(PALETTE[kind][0]) in colours  # box fills
    for box in drawing.boxes.values():  # the text is drawn in every box (from the bundled font)
        assert ink_inside(image, box) > 50 * len(box.node.lines), box.node.id


def test_estd_graph_names_primitives_and_controllers(no_graphviz):
    graph = from_estd(melfa_estd(), "pick_and_place.melfa.estd.xml")
    boxes = {n.id: n.lines for n in graph.nodes}
    assert boxes["grasp"][1:] == ("grasp", "arm: jaw_grasp_correction", "hand: close_until_force", "  grasp_force=15")
    assert "arm: place" in boxes["put_down"] and "hand: squeeze" in boxes["put_down"]
    assert "arm: cartesian_move" in boxes["approach"] and "  target=0.1 -0.05 0.15" in boxes["approach"]
    assert [e.lines for e in graph.edges if e.id == "approach->failed#2"] == [("timeout(20s)",)]
    svg = etree.fromstring(render(graph, "svg")[0])
    assert "hand: close_until_force" in {t.text for t in svg.iter(f"{SVG}text")}


def test_estd_conditions_are_shown_on_request():
    graph = from_estd(melfa_estd(), "p.xml", conditions=True)
    grasped = next(e for e in graph.edges if e.id == "grasp->lift")
    text = " ".join(line.strip() for line in grasped.lines)
    assert "grasp_stable: tactile_force_above[on=tactile_left+tactile_right," in text
    assert len(grasped.lines) > 1  # wrapped: each line as long as the longest unbreakable word allows
    assert all(len(line) <= 44 or " " not in line.strip() for line in grasped.lines)


def test_graphviz_draws_when_installed(tmp_path, monkeypatch):
    fake_dot(tmp_path, monkeypatch, "dot = sys.stdin.read()\n"
             "sys.stdout.write('<svg><!-- ' + sys.argv[1] + ' ' + str(dot.count(' -> ')) + ' --></svg>')")
    data, drawn_by = render(example_graph("pick_and_place.xml"), "svg")
    assert (data, drawn_by) == (b"<svg><!-- -Tsvg 26 --></svg>", "graphviz")


def test_a_failing_graphviz_falls_back_unless_asked_for(tmp_path, monkeypatch):
    fake_dot(tmp_path, monkeypatch, "sys.stderr.write('Error: syntax error in line 1'); sys.exit(1)")
    graph = example_graph("retry_grasp.xml")
    data, drawn_by = render(graph, "png")
    assert data.startswith(b"\x89PNG") and "syntax error in line 1" in drawn_by
    with pytest.raises(GraphvizError, match="syntax error in line 1"):
        render(graph, "png", Renderer.GRAPHVIZ)


def test_graphviz_asked_for_but_missing(no_graphviz):
    with pytest.raises(GraphvizError, match="not installed"):
        render(example_graph("retry_grasp.xml"), "svg", Renderer.GRAPHVIZ)


def test_big_pictures_shrink_then_are_refused(monkeypatch, no_graphviz):
    graph = example_graph("retry_grasp.xml")
    full = png_image(render(graph, "png")[0]).size
    monkeypatch.setattr(png, "MAX_PIXELS", full[0] * full[1] // 2)  # room for 1x but not 2x
    assert png_image(render(graph, "png")[0]).size == (full[0] // 2, full[1] // 2)
    monkeypatch.setattr(png, "MAX_PIXELS", 1000)
    with pytest.raises(PictureTooBig, match=r"too big for a PNG; draw it as \.svg"):
        render(graph, "png")
