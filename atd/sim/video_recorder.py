"""Filming a run: every `FRAME_PERIOD` of simulated time the control loop sends what a
picture of the scene depends on (joint positions, object poses: `SimRobot.scene_state`) to
a process of its own, which poses its own copy of the robot and scene so, renders it,
draws the state and time on it, and encodes the video when the run ends; the run's process
writes the file, as it writes every other output.

The control loop thus pays for a few hundred bytes a frame, not for rendering, which on a
machine without a GPU (software OpenGL) costs as much as the simulation it shows: the two
run side by side on two cores. The process is started afresh (`python -m
atd.sim.video_recorder`), not forked: an OpenGL context, or the threads of a software
renderer, that the run's process may already hold would not survive a fork. It builds
its robot while the first frames wait in the pipe. If its feed ends without the word
"end" (the run raised, was stopped or its engine crashed) it writes nothing.
"""

from __future__ import annotations

import dataclasses
import fcntl
import os
import pickle
import signal
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import BinaryIO

from atd.model.files import OutputError, describe_write_error, write_output
from atd.sim.scene import WORKSPACE_CAMERA, Scene
from atd.sim.simrobot import SimRobot
from factories.description import RobotDescription
from atd.sim.video import DEFAULT_SIZE, FRAME_PERIOD, Frames, VideoError

_END = None  # the feed's last item when the run ended and the video is wanted
PIPE_SIZE = 1 << 20  # bytes: thousands of frames' states, while the process starts and builds its robot


class Recorder:
    """Called every control tick with the robot (and the robot's other arms a task moves) and
    the state it is in; keeps a frame every `FRAME_PERIOD` of simulated time, from `camera`,
    at `size` (width, height)."""

    def __init__(self, path: Path, size: tuple[int, int] = DEFAULT_SIZE, camera: str = WORKSPACE_CAMERA) -> None:
        self.path, self.size, self.camera = path, size, camera
        self._next = 0.0
        self._process: subprocess.Popen | None = None
        self._errors: BinaryIO | None = None  # what the process says on stderr, for when it ends early

    def __call__(self, robot: SimRobot, state: str = "", others: tuple[SimRobot, ...] = ()) -> None:
        now = robot.read().time
        if now < self._next:
            return
        self._next = now + FRAME_PERIOD
        arms = (robot, *others)
        if self._process is None:
            self.start(tuple(a.description for a in arms), robot.scene, robot.engine)
        self._send((now, state, tuple(a.scene_state() for a in arms)))

    def save(self) -> str:
        """Have the video encoded, and write it; what became of it, for the user. OutputError
        when the file system refused it (here, or the encoder's temporary file there)."""
        if self._process is None:
            return f"no video written to {self.path}: the run ended before its first frame"
        self._send(_END)
        self._close_feed()
        said = self._process.stdout.read()
        self._reap()
        if not said:
            return f"no video written to {self.path}: the process rendering it ended early ({self._last_error()})"
        kind, *told = pickle.loads(said)
        if kind == "refused":
            raise OutputError(describe_write_error(self.path, OSError(*told)))
        if kind == "said":
            return told[0]
        data, frames = told
        write_output(self.path, data)
        return f"video: {self.path} ({frames} frames, {self.size[0]}x{self.size[1]}, {self.camera} camera)"

    def abandon(self) -> None:
        """End the rendering process without a video (the run did not end); after `save`, nothing."""
        if self._process is not None:
            self._close_feed()
            self._process.kill()
            self._reap()

    def start(self, arms: tuple[RobotDescription, ...], scene: Scene, engine: str) -> None:
        """Start the rendering process on this robot's arms (as `make_arms` takes them) and
        scene now, before the first frame (by default it starts at the first): it builds its
        copy while the run builds its own."""
        self._errors = tempfile.TemporaryFile()
        self._process = subprocess.Popen(
            [sys.executable, "-m", "atd.sim.video_recorder"], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
            stderr=self._errors, start_new_session=True,  # Ctrl-C stops the run, which tells this process
            env={**os.environ, "PYTHONPATH": os.pathsep.join(p for p in sys.path if p)})  # the modules this one sees
        try:
            fcntl.fcntl(self._process.stdin.fileno(), fcntl.F_SETPIPE_SZ, PIPE_SIZE)
        except (AttributeError, OSError):
            pass  # not Linux, or a lower limit set for this system: the run may wait for the process to start
        self._send((arms, scene, engine, self.path, self.size, self.camera))

    def _send(self, item: object) -> None:
        if self._process is None or self._process.stdin.closed:
            return
        try:
            pickle.dump(item, self._process.stdin, protocol=pickle.HIGHEST_PROTOCOL)
        except BrokenPipeError:  # the process ended: `save` says so
            self._close_feed()

    def _close_feed(self) -> None:
        try:
            self._process.stdin.close()
        except BrokenPipeError:
            pass

    def _reap(self) -> None:
        self._process.wait()
        self._process.stdout.close()
        self._process = None

    def _last_error(self) -> str:
        self._errors.seek(0)
        lines = self._errors.read().decode(errors="replace").strip().splitlines()
        self._errors.close()
        return lines[-1] if lines else "it said nothing"


def film(feed: BinaryIO, answer: BinaryIO) -> None:
    """The rendering process: its robot from the feed's first item, a frame per item after
    it, then the answer: ("video", the file's bytes, frames), ("said", why there is no
    video) or ("refused", errno, message: the encoder's temporary file could not be
    written). Nothing when the feed ends without the word "end"."""
    from atd.sim import make_arms

    try:
        descriptions, scene, engine, path, size, camera = pickle.load(feed)
    except EOFError:
        return
    frames = Frames(path, size, camera)
    try:
        arms = make_arms(descriptions, dataclasses.replace(scene, settle=False), engine)  # posed, never stepped
        failed: str | None = None
    except Exception as exc:  # noqa: BLE001 - said, not raised: the run it films goes on
        failed = f"{type(exc).__name__}: {exc}"
    while (item := _next(feed)) is not _END:
        sim_time, state, scene_states = item
        if failed is None:
            try:
                for arm, scene_state in zip(arms, scene_states):
                    arm.set_scene_state(scene_state)
                frames.add(arms[0].render(*size, camera=camera), sim_time, state)
            except Exception as exc:  # noqa: BLE001 - no OpenGL context, no display: said, not raised
                failed = f"{type(exc).__name__}: {exc}"
    if failed or not frames.frames:
        reply: tuple = ("said", f"no video written to {path}: offscreen rendering failed ({failed or 'no frames'}); "
                                "try MUJOCO_GL=egl or MUJOCO_GL=osmesa")
    else:
        try:
            reply = ("video", frames.encode(), len(frames.frames))
        except VideoError as exc:
            reply = ("said", f"no video written to {path}: {exc}")
        except OSError as exc:
            reply = ("refused", exc.errno, exc.strerror)
    answer.write(pickle.dumps(reply))
    answer.flush()


def _next(feed: BinaryIO) -> object:
    """The feed's next item; SystemExit (no video) when it ends without the word "end"."""
    try:
        return pickle.load(feed)
    except (EOFError, pickle.UnpicklingError):
        raise SystemExit(0) from None


if __name__ == "__main__":
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    film(sys.stdin.buffer, sys.stdout.buffer)
