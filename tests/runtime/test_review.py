"""`atd report` and `atd compare` on real recordings from both engines and every robot."""

from __future__ import annotations

import base64
import gzip
import io
import json
import os
import re
import subprocess
import sys
from pathlib import Path
from typing import NamedTuple

import numpy as np
import pytest
from lxml import etree, html
from PIL import Image

from atd.graph.style import FADED_BORDER, FADED_FILL, TAKEN_WIDTH
from atd.review.load import RecordingError, load
from factories.melfa import description as melfa
from tests.conftest import REPO


class Recorded(NamedTuple):
    task: str
    robot: str
    arm: str
    engine: str
    end: str  # the success state the run reaches
    pads: set[str]  # the hand's tactile pads, each plotted


_PICK, _LIFT = "pick_and_place", "grasp_and_lift"  # grasp_and_lift: the shorter task, for the costlier robots
RUNS = {
    "melfa_mj": Recorded(_PICK, "melfa", "main", "mujoco", "done", {"tactile_left", "tactile_right"}),
    "melfa_pb": Recorded(_PICK, "melfa", "main", "pybullet", "done", {"tactile_left", "tactile_right"}),
    "baxter_mj": Recorded(_LIFT, "baxter", "right", "mujoco", "success_end", {"gripper_left", "gripper_right"}),
    "baxter_pb": Recorded(_LIFT, "baxter", "right", "pybullet", "success_end", {"gripper_left", "gripper_right"}),
    "barrett_mj": Recorded(_LIFT, "tombatossals", "right", "mujoco", "success_end",
                           {"tactile_f1", "tactile_f2", "tactile_f3", "tactile_palm"}),
    "sdh2_pb": Recorded(_LIFT, "tombatossals", "left", "pybullet", "success_end",
                        {"tactile_f1", "tactile_f2", "tactile_f3"}),
    "panda_mj": Recorded(_LIFT, "panda", "main", "mujoco", "success_end", {"tactile_left", "tactile_right"}),
    "panda_pb": Recorded(_LIFT, "panda", "main", "pybullet", "success_end", {"tactile_left", "tactile_right"}),
}


def assert_loads_nothing(page: html.HtmlElement) -> None:
    """No element of the page loads anything from elsewhere (a script, a style sheet, a
    picture, a frame): everything it shows is inline, data: URLs at most."""
    for element in page.iter():
        for attribute in ("src", "href", "data", "poster", "srcset", "{http://www.w3.org/1999/xlink}href"):
            value = (element.get(attribute) or "").strip()
            assert not value or value.startswith(("data:", "#")), f"<{element.tag} {attribute}={value[:80]!r}>"
    assert not page.xpath("//link") and all("url(" not in s for s in page.xpath("//style/text()"))


def bokeh_document(page: html.HtmlElement) -> dict:
    """The figures' document the page's script draws, as JSON."""
    (found,) = [m for s in page.xpath("//script/text()") if (m := re.search(r"docs_json = '(\{.*?)';\n", s))]
    (document,) = json.loads(found.group(1)).values()
    return document


def _objects(node: object, name: str) -> list[dict]:
    """Every Bokeh object called `name` in a document."""
    if isinstance(node, list):
        return [found for item in node for found in _objects(item, name)]
    if not isinstance(node, dict):
        return []
    return ([node] if node.get("name") == name else []) + [found for v in node.values() for found in _objects(v, name)]


def legends(page: html.HtmlElement) -> dict[str, np.ndarray]:
    """Each line of the plots, by its legend's name: its values as the page holds them."""
    document = bokeh_document(page)
    sources = {s["id"]: dict(s["attributes"]["data"]["entries"]) for s in _objects(document, "ColumnDataSource")}
    renderers = {r["id"]: r["attributes"]["data_source"]["id"] for r in _objects(document, "GlyphRenderer")}
    lines = {}
    for item in _objects(document, "LegendItem"):
        (renderer,) = item["attributes"]["renderers"]
        lines[item["attributes"]["label"]["value"]] = array(sources[renderers[renderer["id"]]]["v"])
    return lines


def array(column: dict | list) -> np.ndarray:
    """A column of a Bokeh data source: a list, or an array as bytes (base64, maybe gzipped)."""
    if isinstance(column, list):
        return np.array(column, float)
    data = base64.b64decode(column["array"]["data"])
    return np.frombuffer(gzip.decompress(data) if data[:2] == b"\x1f\x8b" else data, column["dtype"])


def _below_label(source: str) -> np.ndarray:
    """A key frame's pixels under its label (the state and time, drawn at the top)."""
    picture = Image.open(io.BytesIO(base64.b64decode(source.split(",", 1)[1]))).convert("L")
    return np.asarray(picture, float)[picture.height // 6:]


def _atd(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "atd", *args], cwd=cwd, capture_output=True, text=True, timeout=300)


class _Recordings(dict):
    """Each run of RUNS recorded (at 50 Hz) the first time a test asks for it."""

    def __init__(self, folder: Path) -> None:
        super().__init__()
        self.folder = folder

    def __missing__(self, name: str) -> Path:
        run = RUNS[name]
        path = self.folder / f"{name}.mcap"
        result = _atd("run", str(REPO / "examples" / f"{run.task}.xml"), "--robot", run.robot, "--arm", run.arm,
                      "--engine", run.engine, "-q", "--record", str(path), "--rate", "50", cwd=self.folder)
        assert result.returncode == 0, result.stderr
        self[name] = path
        return path


@pytest.fixture(scope="module")
def recordings(tmp_path_factory) -> _Recordings:
    return _Recordings(tmp_path_factory.mktemp("recordings"))


class _Pages(dict):
    """The text of each recording's `atd report` page, made the first time a test asks for it."""

    def __init__(self, recordings: _Recordings, folder: Path) -> None:
        super().__init__()
        self.recordings, self.folder = recordings, folder

    def __missing__(self, name: str) -> str:
        page = self.folder / f"{name}.html"
        result = _atd("report", str(self.recordings[name]), "-o", str(page), cwd=self.folder)
        assert result.returncode == 0, result.stderr
        self[name] = page.read_text()
        return self[name]


@pytest.fixture(scope="module")
def pages(recordings, tmp_path_factory) -> _Pages:
    return _Pages(recordings, tmp_path_factory.mktemp("pages"))


@pytest.mark.parametrize("name", list(RUNS))
def test_the_report_is_one_offline_page_with_the_graph_every_plot_and_the_events(recordings, pages, name) -> None:
    run, text = RUNS[name], pages[name]
    tree = html.fromstring(text)
    assert_loads_nothing(tree)
    (node,) = tree.xpath("//figure[@id='graph']")
    assert node.xpath(".//*[local-name()='svg']"), "the graph is an SVG"
    for figure in ("timeline", "signals"):
        (node,) = tree.xpath(f"//figure[@id='{figure}']")
        assert node.xpath(".//div[@data-root-id]"), f"{figure} is drawn by the page's own BokehJS"
    graph = etree.tostring(tree.xpath("//figure[@id='graph']")[0], encoding="unicode")
    assert "visited 1x" in graph and "grasp" in graph
    assert f"succeeded: reached &#39;{run.end}&#39;" in text or f"succeeded: reached '{run.end}'" in text
    assert set(legends(tree)) >= run.pads, "a pad-force line for each of the hand's pads"
    entered = [r for r in load(recordings[name]).trace if r.type == "enter" and "/" not in r.state]
    frames = tree.xpath("//figure[@id='keyframes']/img")
    assert [f.get("alt") for f in frames] == [f"{r.state} at {r.t:.2f} s" for r in entered], "a picture per state entered"
    assert all(f.get("src").startswith("data:image/jpeg;base64,") for f in frames)
    scenes = [_below_label(f.get("src")) for f in frames]
    moved = sum(np.abs(a - b).mean() > 1.0 for a, b in zip(scenes, scenes[1:]))
    assert moved >= len(frames) // 2, "the pictures show the run moving, not one moment labelled again and again"
    events = tree.xpath("//table[@id='events']//tr")[1:]
    fired = load(recordings[name]).events()
    assert len(events) == len(fired) and any("grasp_stable" in r.text_content() for r in events)


@pytest.fixture(scope="module")
def melfa_page(pages) -> html.HtmlElement:
    """The report of the Melfa's pick and place in MuJoCo, as a browser would parse it."""
    return html.fromstring(pages["melfa_mj"])


def _graph_svg(page: html.HtmlElement) -> etree._Element:
    (svg,) = page.xpath("//figure[@id='graph']/*[local-name()='svg']")
    return svg


def _boxes(svg: etree._Element) -> dict[str, str]:
    """Each state's fill, from the library layout's SVG or graphviz's."""
    fills = {}
    for g in svg.iter("{*}g"):
        name = g.get("data-state") or (g.findtext("{*}title") if g.get("class") == "node" else None)
        if name:
            fills[name] = next(e.get("fill") for e in g if e.get("fill") not in (None, "none"))
    return fills


def _arrows(svg: etree._Element) -> list[tuple[str, float]]:
    """Each arrow's colour and width."""
    return [(path.get("stroke"), float(path.get("stroke-width", 1))) for g in svg.iter("{*}g")
            if g.get("class") == "edge" for path in g.iter("{*}path") if path.get("fill") == "none"]


def test_the_report_colours_the_path_taken_and_folds_the_failure_fan(melfa_page) -> None:
    svg = _graph_svg(melfa_page)
    fills = _boxes(svg)
    path = ["approach", "descend", "grasp", "lift", "carry", "put_down", "let_go", "retreat", "done"]
    assert fills["failed"] == FADED_FILL and all(fills[state] != FADED_FILL for state in path)
    arrows = _arrows(svg)
    assert [w for _, w in arrows].count(TAKEN_WIDTH) == len(path) - 1, "each transition taken drawn thick"
    grey = [colour for colour, _ in arrows if colour == FADED_BORDER]
    assert len(grey) == 8, "one grey arrow into 'failed' per state, not the 18 failure transitions"
    (note,) = melfa_page.xpath("//figure[@id='graph']/following-sibling::p[1]")
    assert "The 15 failure transitions never taken are folded into 5 grey arrows" in note.text_content()


def test_the_report_draws_the_graph_at_a_readable_size_and_scrolls_it(melfa_page) -> None:
    css = re.sub(r"/\*.*?\*/", "", " ".join(melfa_page.xpath("//style/text()")), flags=re.S)
    rules = {selector.strip(): body for selector, body in re.findall(r"([^{}]+)\{([^}]*)\}", css)}
    assert "overflow: auto" in rules["#graph"], "the graph scrolls"
    assert "max-width: none" in rules["#graph svg"], "the graph is not shrunk to the page's width"
    svg = _graph_svg(melfa_page)
    width = float(re.match(r"[\d.]+", svg.get("width")).group())
    assert width == float(svg.get("viewbox").split()[2]), "drawn at its own scale"  # an HTML parser lowercases
    sizes = [float(e.get("font-size")) for e in svg.iter() if e.get("font-size")]
    assert sizes and min(sizes) >= 11, "text at least 11 px"


def test_the_report_names_each_joint_as_the_robot_does(melfa_page) -> None:
    """The legends say the Melfa's j1..j6 and its jaw's `grip`, where they said q1..q6 and `dof 0`."""
    robot = melfa.description()
    lines = legends(melfa_page)
    assert {*robot.arm_joints, *(dof.name for dof in robot.hand.dofs)} <= set(lines)
    assert not {"q1", "dof 0"} & set(lines)


def test_the_report_plots_zoom_together_with_their_data_and_bokeh_inline(melfa_page, recordings) -> None:
    """Every time plot shares one time axis (a zoom on one zooms all); the page carries
    BokehJS itself, and the lines' values: the 15 N grip on both pads, the object lifted."""
    scripts = melfa_page.xpath("//script")
    assert not [s for s in scripts if s.get("src")] and any("BEGIN bokeh.min.js" in (s.text or "") for s in scripts)
    document = bokeh_document(melfa_page)
    figures = _objects(document, "Figure")
    assert len(figures) == 6, "the timeline and five signal panels"
    assert len({f["attributes"]["x_range"]["id"] for f in figures}) == 1, "one time axis shared by every plot"
    lines = legends(melfa_page)
    assert all(14 < np.nanmax(lines[pad]) < 17 for pad in ("tactile_left", "tactile_right"))
    assert np.nanmax(lines["object z"]) - np.nanmin(lines["object z"]) > 0.1, "the object's true lift, 0.12 m"
    strips = [r for r in _objects(document, "GlyphRenderer") if r["attributes"]["glyph"]["name"] == "VStrip"]
    assert len(strips) == 2 * 5, "each of the five panels shades the stays, in two alternating colours"
    sources = {s["id"]: dict(s["attributes"]["data"]["entries"]) for s in _objects(document, "ColumnDataSource")}
    shaded = sorted(x for r in strips[:2] for x in array(sources[r["attributes"]["data_source"]["id"]]["x0"]))
    assert shaded == pytest.approx([r.t for r in load(recordings["melfa_mj"]).trace if r.type == "enter"])


def test_without_opengl_the_report_says_why_it_has_no_pictures(recordings, tmp_path) -> None:
    page = tmp_path / "report.html"
    result = subprocess.run([sys.executable, "-m", "atd", "report", str(recordings["melfa_mj"]), "-o", str(page)],
                            cwd=tmp_path, capture_output=True, text=True, timeout=300,
                            env={**os.environ, "MUJOCO_GL": "nonsense"})
    assert result.returncode == 0 and "Traceback" not in result.stderr, result.stderr
    tree = html.fromstring(page.read_text())
    assert not tree.xpath("//figure[@id='keyframes']")
    (said,) = tree.xpath("//p[@id='no-keyframes']")
    assert "offscreen rendering failed" in said.text_content() and "MUJOCO_GL=egl" in said.text_content()
    assert tree.xpath("//figure[@id='signals']//div[@data-root-id]"), "the rest of the page is there"


def test_the_report_says_how_to_see_the_same_recording_in_3d_in_foxglove(melfa_page, recordings) -> None:
    (note,) = melfa_page.xpath("//p[@id='foxglove']")
    text = note.text_content()
    assert "Foxglove" in text and str(recordings["melfa_mj"].resolve()) in text
    assert str(REPO / "docs" / "foxglove-layout.json") in text and (REPO / "docs" / "foxglove-layout.json").is_file()


@pytest.mark.parametrize("a, b", [("melfa_mj", "melfa_pb"), ("panda_mj", "panda_pb"), ("barrett_mj", "sdh2_pb"),
                                  ("baxter_mj", "baxter_pb")])
def test_compare_aligns_two_runs_state_by_state(recordings, a, b, tmp_path) -> None:
    plot = tmp_path / "diff.svg"
    result = _atd("compare", str(recordings[a]), str(recordings[b]), "--plot", str(plot), cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    states = [r.state for r in load(recordings[a]).trace if r.type == "enter"]
    rows = {line.split()[0]: line for line in result.stdout.splitlines() if line and line.split()[0] in states}
    assert set(rows) == set(states), "a row for every state both runs entered"
    holding = "carry" if RUNS[a].task == _PICK else "lift_object"
    (pad_force_a,) = re.findall(r"\(A ([-\d.e+]+)\)", rows[holding])[:1]
    assert float(pad_force_a) > 1.0, "while the object is held, A's mean pad force is the grip's"
    if a == "melfa_mj":
        assert "(A 15" in rows["carry"], "A's pad force while carrying is the 15 N grasp force"
    assert etree.fromstring(plot.read_bytes()).tag.endswith("svg")


def test_compare_as_json_gives_each_state_both_durations_and_each_signals_means(recordings, tmp_path) -> None:
    result = _atd("compare", str(recordings["melfa_mj"]), str(recordings["melfa_pb"]), "--format", "json", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    found = json.loads(result.stdout)
    assert (found["runs"]["a"]["engine"], found["runs"]["b"]["engine"]) == ("mujoco", "pybullet")
    assert found["runs"]["a"]["path"] == str(recordings["melfa_mj"]) and found["plot"] is None
    states = {row["state"]: row for row in found["states"]}
    assert [r.state for r in load(recordings["melfa_mj"]).trace if r.type == "enter"] == list(states)
    assert all(row["time_a"] > 0 and row["time_b"] > 0 for row in found["states"] if row["state"] != "done")
    carry = states["carry"]["signals"]["pad force (N)"]
    assert abs(carry["mean_a"] - 15) < 1.5 and abs(carry["difference"]) < 5  # the 15 N grasp in both engines


def test_report_and_compare_refuse_what_is_not_a_recording(tmp_path) -> None:
    bogus = tmp_path / "x.mcap"
    bogus.write_text("not mcap")
    for args in (("report", str(bogus)), ("compare", str(bogus), str(bogus))):
        result = _atd(*args, cwd=tmp_path)
        assert result.returncode == 1 and "not an MCAP recording" in result.stderr and "Traceback" not in result.stderr


def test_a_corrupted_recording_is_refused_in_one_line(recordings, tmp_path) -> None:
    """Bytes flipped inside a compressed chunk raised zstandard's ZstdError as a traceback."""
    data = bytearray(recordings["melfa_mj"].read_bytes())
    for i in range(len(data) // 4, len(data) // 2, 97):
        data[i] ^= 0xFF
    broken = tmp_path / "broken.mcap"
    broken.write_bytes(bytes(data))
    with pytest.raises(RecordingError, match="not an MCAP recording"):
        load(broken)
    result = _atd("report", str(broken), cwd=tmp_path)
    assert result.returncode == 1 and "Traceback" not in result.stderr and result.stderr.count("\n") == 1
