"""`atd run --video`: a GIF that Pillow reads, at the asked size, from the asked camera, with
the state and the simulated time drawn on every frame; bad sizes and cameras in one line."""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest
from PIL import Image

from atd.sim import load_description, make_robot
from atd.sim.video import draw_label
from atd.sim.video_recorder import Recorder
from tests.runtime.test_run_cli import PICK_AND_PLACE, SHORT_MOVE


def atd(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "atd", *args], capture_output=True, text=True, timeout=300)


def _frames(path) -> list[np.ndarray]:
    with Image.open(path) as gif:
        frames = []
        for index in range(gif.n_frames):
            gif.seek(index)
            frames.append(np.asarray(gif.convert("RGB")))
        return frames


def test_the_gif_has_the_asked_size_and_the_state_and_time_on_every_frame(tmp_path, atd_file):
    path = atd_file(SHORT_MOVE)
    gif = tmp_path / "run.gif"
    result = atd("run", str(path), "--robot", "melfa", "--video", str(gif), "--video-size", "320x240", "-q")
    assert result.returncode == 0, result.stderr
    frames = _frames(gif)
    assert f"video: {gif} ({len(frames)} frames, 320x240, workspace camera)" in result.stdout
    assert len(frames) >= 5 and all(f.shape == (240, 320, 3) for f in frames)  # 10 frames a simulated second
    label = [f[:20, :80].astype(int) for f in frames]  # the top-left corner, where the label is
    assert all(corner.max() > 200 and corner.min() < 60 for corner in label)  # white text on a dark band
    assert np.abs(label[0] - label[-1]).max() > 100  # the time drawn changes
    assert frames[0][120:].std() > 10  # and the scene is lit, not a dark uniform picture


def test_draw_label_draws_in_the_corner_and_leaves_the_rest():
    frame = np.full((120, 160, 3), 128, np.uint8)
    labelled = np.asarray(draw_label(frame, "1.20 s  grasp"))
    assert labelled[:12, :60].std() > 20 and (labelled[60:] == 128).all()


@pytest.mark.parametrize("size", ["640", "641x480", "8x8", "640x480x3", "wide"])
def test_a_bad_video_size_is_one_line(tmp_path, size):
    result = atd("run", PICK_AND_PLACE, "--robot", "melfa", "--video", str(tmp_path / "run.gif"), "--video-size", size)
    assert result.returncode == 2
    assert result.stderr.strip() == (f"error: --video-size {size}: give WIDTHxHEIGHT in pixels, e.g. 640x480, "
                                     "each an even number from 64 to 3840")


def test_an_unknown_camera_is_one_line_naming_the_cameras(tmp_path):
    result = atd("run", PICK_AND_PLACE, "--robot", "melfa", "--video", str(tmp_path / "run.gif"), "--camera", "top")
    assert result.returncode == 2
    assert result.stderr.strip() == "error: --camera top: melfa has no such camera; choose one of: workspace, kinect"
    assert not (tmp_path / "run.gif").exists()


def test_camera_without_video_is_refused():
    result = atd("run", PICK_AND_PLACE, "--robot", "melfa", "--camera", "kinect")
    assert result.returncode == 2
    assert result.stderr.strip() == "error: --camera: there is no video to shape; give --video FILE.gif too"


@pytest.mark.parametrize("engine", ["mujoco", "pybullet"])
def test_each_engine_renders_from_the_robots_camera_and_refuses_another(engine):
    robot = make_robot(load_description("melfa"), engine=engine)
    try:
        workspace, kinect = robot.render(96, 64), robot.render(96, 64, camera="kinect")
        assert workspace.shape == kinect.shape == (64, 96, 3)
        assert np.abs(workspace.astype(int) - kinect).mean() > 10  # another viewpoint
        with pytest.raises(LookupError, match="no camera 'top'"):
            robot.render(96, 64, camera="top")
    finally:
        robot.close()


def test_a_run_that_does_not_end_leaves_no_video_and_no_rendering_process(tmp_path):
    robot = make_robot(load_description("melfa"))
    recorder = Recorder(tmp_path / "run.gif")
    try:
        for _ in range(100):
            robot.step()
            recorder(robot, "moving")
        rendering = recorder._process.pid
        recorder.abandon()
    finally:
        robot.close()
    with pytest.raises(ProcessLookupError):
        os.kill(rendering, 0)  # ended and reaped
    assert list(tmp_path.iterdir()) == []
