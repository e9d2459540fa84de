"""`atd graph` as a user meets it: files written or not, messages, exit codes."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys

import numpy as np
import pytest
from click.testing import CliRunner
from lxml import etree

from atd.cli import main
from benchmarks.bench_validate import generate
from atd.graph.source import read_graph
from tests.conftest import EXAMPLES, KNOWN_BOX
from tests.graph.test_render import SVG, png_image


@pytest.fixture(autouse=True)
def no_graphviz(monkeypatch):
    monkeypatch.setattr(shutil, "which", lambda name, *a, **k: None)


def atd(*args: str):
    return CliRunner().invoke(main, list(args))


def test_draws_an_atd_in_every_format(tmp_path):
    for fmt in ("dot", "svg", "png"):
        out = tmp_path / f"pick.{fmt}"
        result = atd("graph", str(EXAMPLES / "pick_and_place.xml"), "-o", str(out))
        assert result.exit_code == 0, result.output
        assert f"wrote {out} (10 states, 26 transitions;" in result.output
        assert out.stat().st_size > 1000
    assert "the library layout (grandalf)" in result.output
    assert (tmp_path / "pick.dot").read_text().startswith("digraph task {")
    etree.parse(str(tmp_path / "pick.svg"))
    assert (tmp_path / "pick.png").read_bytes().startswith(b"\x89PNG")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pick.dot", "pick.png", "pick.svg"]  # no temp files


def test_an_estd_is_drawn_without_graphviz_with_every_state_and_event_shown(tmp_path):
    estd = tmp_path / "pp.estd.xml"
    assert atd("translate", str(EXAMPLES / "pick_and_place.xml"), "-r", "melfa", "-o", str(estd), "-q").exit_code == 0
    result = atd("graph", str(estd), "-o", str(tmp_path / "pp.svg"), "--conditions")
    assert result.exit_code == 0, result.output
    graph, _ = read_graph(estd, conditions=True)
    shown = [t.text for t in etree.parse(str(tmp_path / "pp.svg")).iter(f"{SVG}text")]
    assert set(shown) >= {line for item in graph.nodes + graph.edges for line in item.lines}
    (tmp_path / "bin").mkdir()  # a PATH with no programs on it: no graphviz, for certain
    done = subprocess.run([sys.executable, "-m", "atd", "graph", str(estd), "-o", str(tmp_path / "pp.png")],
                          env={**os.environ, "PATH": str(tmp_path / "bin")}, capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 0, done.stderr
    assert "(10 states, 26 transitions; the library layout (grandalf))" in done.stdout
    image = np.asarray(png_image((tmp_path / "pp.png").read_bytes()))
    assert image.shape[0] > 1000 and image.shape[1] > 1000
    assert (image.sum(axis=2) < 200).sum() > 20_000  # text and lines, not a blank page


def test_draws_a_translated_estd_with_its_subtask(tmp_path):
    for name in ("empty_the_box.xml", "pick_one.xml"):
        shutil.copy(KNOWN_BOX / name, tmp_path / name)
    estd = tmp_path / "box.estd.xml"
    assert atd("translate", str(tmp_path / "empty_the_box.xml"), "-r", "melfa", "-o", str(estd), "-q").exit_code == 0
    result = atd("graph", str(estd), "-o", str(tmp_path / "box.dot"), "--conditions")
    assert result.exit_code == 0, result.output
    dot = (tmp_path / "box.dot").read_text()
    assert "ESTD for melfa" in dot
    assert '"pick_one" [label="pick_one\\ntask\\nfile: pick_one.xml\\n9 states"' in dot
    assert '"pick_one" -> "box_empty" [label="error: subtask_failed"' in dot


def test_invalid_atd_is_refused_and_nothing_written(tmp_path):
    task = tmp_path / "bad.xml"
    task.write_text('<statemachine>\n  <state name="a" type="move"/>\n'
                    '  <transition origin="a" destination="nowhere"><success/></transition>\n</statemachine>\n')
    result = atd("graph", str(task), "-o", str(tmp_path / "bad.svg"))
    assert result.exit_code == 1
    assert f"{task}:3:" in result.output and "nowhere" in result.output
    assert f"{task}: cannot be drawn; nothing written" in result.output
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.xml"]


def test_unreadable_estd_is_refused(tmp_path):
    estd = tmp_path / "broken.estd.xml"
    estd.write_text('<estd version="1" robot="melfa" arm="main" initial="a"><state name="a" type="move" atd="a">'
                    '<arm controller="warp_drive"/></state></estd>')
    result = atd("graph", str(estd), "-o", str(tmp_path / "b.png"))
    assert result.exit_code == 1
    assert "error[ESTD100]: schema: Element 'arm', attribute 'controller'" in result.output and "'warp_drive'" in result.output
    assert not (tmp_path / "b.png").exists()


def test_a_file_that_is_neither_atd_nor_estd(tmp_path):
    other = tmp_path / "page.xml"
    other.write_text("<html><body/></html>\n")
    result = atd("graph", str(other), "-o", str(tmp_path / "p.svg"))
    assert result.exit_code == 1
    assert f"{other}:1:1: error[GRF001]: root element is <html>, neither <statemachine>" in result.output


def test_transition_to_an_undefined_state_in_an_estd(tmp_path):
    estd = tmp_path / "hand_edited.estd.xml"
    estd.write_text('<estd version="1" robot="melfa" arm="main" initial="a"><state name="a" type="success" atd="a"/>'
                    '<transition origin="a" destination="b" atd="a->b"><event type="success" atd="a->b/success">'
                    '<condition kind="arm_done" atd="a->b/success"/></event></transition></estd>')
    result = atd("graph", str(estd), "-o", str(tmp_path / "p.svg"))
    assert result.exit_code == 1
    assert "error[GRF002]: transition 'a->b' names state 'b', which is not defined" in result.output


def test_unknown_extension_is_a_usage_error(tmp_path):
    result = atd("graph", str(EXAMPLES / "simple_move.xml"), "-o", str(tmp_path / "task.pdf"))
    assert result.exit_code == 2
    assert "must end in .dot, .svg or .png" in result.output
    assert list(tmp_path.iterdir()) == []


def test_graphviz_asked_for_but_missing_is_a_usage_error(tmp_path):
    result = atd("graph", str(EXAMPLES / "simple_move.xml"), "-o", str(tmp_path / "t.svg"), "--renderer", "graphviz")
    assert result.exit_code == 2
    assert "graphviz is not installed" in result.output and "--renderer builtin" in result.output
    assert list(tmp_path.iterdir()) == []


def test_a_task_too_big_for_the_library_layout_is_refused_with_what_to_do(tmp_path):
    task = tmp_path / "huge.xml"
    task.write_bytes(generate(301, 900))
    result = atd("graph", str(task), "-o", str(tmp_path / "huge.svg"))
    assert result.exit_code == 2
    assert f"error: {task}: 301 states and 900 transitions are more than the library layout draws" in result.output
    assert "install graphviz, or write .dot" in result.output
    assert sorted(p.name for p in tmp_path.iterdir()) == ["huge.xml"]
