"""`atd report` and `atd compare` on real recordings from both engines."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest
from lxml import etree, html

from tests.conftest import REPO


def _atd(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "atd", *args], cwd=cwd, capture_output=True, text=True, timeout=300)


@pytest.fixture(scope="module")
def recordings(tmp_path_factory) -> dict[str, Path]:
    """The Melfa's pick-and-place recorded in MuJoCo and PyBullet, and Baxter's in MuJoCo."""
    folder = tmp_path_factory.mktemp("recordings")
    found = {}
    for name, robot, engine in (("melfa_mj", "melfa", "mujoco"), ("melfa_pb", "melfa", "pybullet"),
                                ("baxter_mj", "baxter", "mujoco")):
        path = folder / f"{name}.mcap"
        result = _atd("run", str(REPO / "examples" / "pick_and_place.xml"), "--robot", robot, "--engine", engine,
                      "-q", "--record", str(path), "--rate", "50", cwd=folder)
        assert result.returncode == 0, result.stderr
        found[name] = path
    return found


@pytest.mark.parametrize("name", ["melfa_mj", "melfa_pb", "baxter_mj"])
def test_the_report_is_one_offline_page_with_the_graph_every_plot_and_the_events(recordings, name, tmp_path) -> None:
    page = tmp_path / "report.html"
    result = _atd("report", str(recordings[name]), "-o", str(page), cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    text = page.read_text()
    assert not re.search(r"""(src|href)\s*=\s*["']?(https?:)?//""", text), "the page must fetch nothing"
    urls = set(re.findall(r"https?://[^\s\"'<>]+", text))
    declared = set(re.findall(r"""xmlns(?::\w+)?=["'](https?://[^"']+)["']""", text))
    assert urls <= declared, f"the page names URLs other than XML namespaces: {urls - declared}"
    tree = html.fromstring(text)
    for figure in ("graph", "timeline", "signals"):
        (node,) = tree.xpath(f"//figure[@id='{figure}']")
        assert node.xpath(".//*[local-name()='svg']"), f"{figure} holds an SVG"
    graph = etree.tostring(tree.xpath("//figure[@id='graph']")[0], encoding="unicode")
    assert "visited 1x" in graph and "grasp" in graph
    assert "succeeded: reached &#39;done&#39;" in text or "succeeded: reached 'done'" in text
    events = tree.xpath("//table[@id='events']//tr")
    assert len(events) > 8 and "grasp_stable" in etree.tostring(events[0].getparent(), encoding="unicode")


def test_compare_aligns_two_engines_state_by_state(recordings, tmp_path) -> None:
    plot = tmp_path / "diff.svg"
    result = _atd("compare", str(recordings["melfa_mj"]), str(recordings["melfa_pb"]), "--plot", str(plot),
                  cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    rows = {line.split()[0]: line for line in result.stdout.splitlines() if line and line.split()[0] in (
        "approach", "descend", "grasp", "lift", "carry", "put_down", "let_go", "retreat")}
    assert len(rows) == 8
    assert "(A 15" in rows["carry"], "A's pad force while carrying is the 15 N grasp force"
    assert etree.fromstring(plot.read_bytes()).tag.endswith("svg")


def test_report_and_compare_refuse_what_is_not_a_recording(tmp_path) -> None:
    bogus = tmp_path / "x.mcap"
    bogus.write_text("not mcap")
    for args in (("report", str(bogus)), ("compare", str(bogus), str(bogus))):
        result = _atd(*args, cwd=tmp_path)
        assert result.returncode == 1 and "not an MCAP recording" in result.stderr and "Traceback" not in result.stderr
