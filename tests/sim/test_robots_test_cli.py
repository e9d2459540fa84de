"""`atd robots test` passes for every robot and hand on both engines, and says why when it cannot run."""

from __future__ import annotations

import pytest
from click.testing import CliRunner
from PIL import Image

from atd.cli import main
from atd.sim import variants
from factories.registry import BUILTIN, installed


def test_the_three_robots_and_both_tombatossals_hands_are_there() -> None:
    assert [v for v in variants() if v[0] in BUILTIN] == [
        ("baxter", "right"), ("baxter", "left"), ("melfa", "main"), ("tombatossals", "right"), ("tombatossals", "left"),
    ]


@pytest.mark.parametrize(("robot", "arm"), variants())
def test_every_robot_passes_its_self_test(robot: str, arm: str | None, engine: str) -> None:
    args = ["robots", "test", robot, "--engine", engine] + (["--arm", arm] if arm else [])
    result = CliRunner().invoke(main, args)
    assert result.exit_code == 0, result.output
    assert "7/7 checks passed" in result.output
    assert "FAIL" not in result.output


def test_unknown_robot_is_named_with_the_known_ones() -> None:
    result = CliRunner().invoke(main, ["robots", "test", "melfaa"])
    assert result.exit_code == 2
    assert "no robot 'melfaa' is installed" in result.output
    assert f"installed: {', '.join(installed())}" in result.output


def test_an_arm_the_robot_does_not_have_is_refused() -> None:
    result = CliRunner().invoke(main, ["robots", "test", "melfa", "--arm", "left"])
    assert result.exit_code == 2
    assert "robot 'melfa' has no arm 'left'; choose one of: main" in result.output


def test_video_other_than_gif_or_mp4_is_refused_before_running(tmp_path) -> None:
    result = CliRunner().invoke(main, ["robots", "test", "melfa", "--video", str(tmp_path / "run.avi")])
    assert result.exit_code == 2
    assert "name the file *.gif or *.mp4" in result.output and "PASS" not in result.output


def test_video_is_written_as_an_animated_gif(tmp_path) -> None:
    video = tmp_path / "grasp.gif"
    result = CliRunner().invoke(main, ["robots", "test", "melfa", "--video", str(video)])
    assert result.exit_code == 0, result.output
    frames = int(result.output.split(" frames")[0].rsplit("(", 1)[1])
    with Image.open(video) as gif:
        assert gif.format == "GIF" and gif.size == (640, 480) and gif.n_frames == frames > 50
