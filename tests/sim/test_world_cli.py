"""`atd run TASK --world WORLD.toml`, as a user meets it: the world it says is true, in
both engines; a bad world file is a located error and exit 1, never a traceback."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from mcap.reader import make_reader

from tests.conftest import EXAMPLES

SIMPLE_MOVE = str(EXAMPLES / "simple_move.xml")
WORLD = """
[[container]]
name = "box"
position = [0.3, 0.15]
size = [0.30, 0.25, 0.10]

[[object]]
library = "speaker"
position = [0.0, -0.3]

[[drop]]
objects = ["duck", "mug", "ball"]
into = "box"
"""


def atd(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "atd", *args], capture_output=True, text=True, timeout=300)


@pytest.mark.parametrize("engine", ["mujoco", "pybullet"])
def test_a_task_runs_in_the_world_the_file_describes(tmp_path: Path, engine: str) -> None:
    world = tmp_path / "world.toml"
    world.write_text(WORLD)
    result = atd("run", SIMPLE_MOVE, "--robot", "melfa", "--engine", engine, "--world", str(world), "-q")
    assert result.returncode == 0, result.stdout + result.stderr
    out = result.stdout.splitlines()
    rests = next(line for line in out if line.startswith("the objects rest at: "))
    assert [part.split(" (")[0] for part in rests.removeprefix("the objects rest at: ").split("), ")] == [
        "speaker", "duck", "mug", "ball"]
    assert "in 'box' at the end: duck, mug, ball (3 of 4 objects)" in out
    assert any(line.startswith("the world settled in ") for line in out)


def test_a_recording_holds_every_object_s_true_pose(tmp_path: Path) -> None:
    world, recording = tmp_path / "world.toml", tmp_path / "run.mcap"
    world.write_text(WORLD)
    result = atd("run", SIMPLE_MOVE, "--robot", "melfa", "--world", str(world), "--record", str(recording), "-q")
    assert result.returncode == 0, result.stderr
    with recording.open("rb") as f:
        truth = [json.loads(m.data) for _, channel, m in make_reader(f).iter_messages() if channel.topic == "/truth"]
    last = truth[-1]
    assert list(last["objects"]) == ["speaker", "duck", "mug", "ball"]
    assert last["object"] == last["objects"]["speaker"]  # the first object, where readers look for one
    assert last["objects"]["speaker"]["position"]["x"] == pytest.approx(0.0, abs=0.01)


def test_a_bad_world_file_is_a_located_error_and_exit_1(tmp_path: Path) -> None:
    world = tmp_path / "world.toml"
    world.write_text(WORLD.replace('"mug"', '"mugg"').replace("[0.0, -0.3]", "[0.0, -0.9]"))
    result = atd("run", SIMPLE_MOVE, "--robot", "melfa", "--world", str(world), "-q")
    assert result.returncode == 1 and "Traceback" not in result.stderr
    assert f"{world}:9:1: error[WLD021]: (0, -0.9) is not over the table" in result.stderr
    assert f"{world}:12:1: error[WLD020]: no object 'mugg' in the library\n  hint: did you mean 'mug'?" in result.stderr
    missing = atd("run", SIMPLE_MOVE, "--robot", "melfa", "--world", str(tmp_path / "none.toml"), "-q")
    assert missing.returncode == 1 and "error[WLD001]: cannot read the world file" in missing.stderr
    assert "Traceback" not in missing.stderr
