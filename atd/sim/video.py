"""Recording a run as a video: an animated GIF written here with numpy alone, or an MP4
encoded by ffmpeg when one is installed (the `video` extra brings one: imageio-ffmpeg).

The GIF is written with an uncompressed LZW stream (a clear code every 254 pixels keeps
the code width at 9 bits): larger files than a real encoder makes, but a few lines of
numpy and readable by every viewer. Frames use a fixed 3-3-2 bit colour palette.
"""

from __future__ import annotations

import errno
import os
import shutil
import struct
import subprocess
from pathlib import Path

import numpy as np

from atd.model import replacing, write_atomically
from atd.model.files import OutputError, describe_write_error

FORMATS = (".gif", ".mp4")
WIDTH, HEIGHT = 320, 240
FRAME_PERIOD = 0.1  # s of simulated time between frames
_CLEAR, _END = 256, 257
# Failures of ffmpeg that are the file system's, reported like those of any other output.
_WRITE_ERRORS = (errno.ENOSPC, errno.EDQUOT, errno.EFBIG, errno.EACCES, errno.EROFS)
_RUN = 254  # pixel codes between clear codes


def _palette() -> bytes:
    i = np.arange(256)
    rgb = np.stack([(i >> 5) * 255 // 7, ((i >> 2) & 7) * 255 // 7, (i & 3) * 255 // 3], axis=1)
    return rgb.astype(np.uint8).tobytes()


def _indices(frame: np.ndarray) -> np.ndarray:
    f = frame.astype(np.uint16)
    return ((f[..., 0] >> 5) << 5 | (f[..., 1] >> 5) << 2 | (f[..., 2] >> 6)).ravel()


def _lzw(pixels: np.ndarray) -> bytes:
    n = len(pixels)
    chunks = -(-n // _RUN)
    codes = np.full(chunks * (_RUN + 1), -1, dtype=np.int32)
    codes[:: _RUN + 1] = _CLEAR
    body = np.arange(len(codes)) % (_RUN + 1) != 0
    codes[np.flatnonzero(body)[:n]] = pixels
    codes = np.concatenate([codes[codes >= 0], [_END]])
    bits = ((codes[:, None] >> np.arange(9)) & 1).astype(np.uint8).ravel()
    data = np.packbits(bits, bitorder="little").tobytes()
    blocks = b"".join(bytes([len(data[i : i + 255])]) + data[i : i + 255] for i in range(0, len(data), 255))
    return bytes([8]) + blocks + b"\x00"


def write_gif(path: Path, frames: list[np.ndarray], frame_period: float = FRAME_PERIOD) -> None:
    """Write RGB frames (h, w, 3) as a looping GIF, atomically."""
    height, width = frames[0].shape[:2]
    delay = max(1, round(frame_period * 100))
    out = [b"GIF89a", struct.pack("<HHBBB", width, height, 0xF7, 0, 0), _palette()]
    out.append(b"\x21\xff\x0bNETSCAPE2.0\x03\x01\x00\x00\x00")  # loop for ever
    for frame in frames:
        out.append(struct.pack("<BBBBHBB", 0x21, 0xF9, 4, 0, delay, 0, 0))
        out.append(struct.pack("<BHHHHB", 0x2C, 0, 0, width, height, 0))
        out.append(_lzw(_indices(frame)))
    out.append(b"\x3b")
    write_atomically(path, b"".join(out))


class VideoError(Exception):
    """The video cannot be written; the message says what to do instead."""


def mp4_encoder() -> str | None:
    """The ffmpeg that writes MP4: imageio-ffmpeg's when installed, else one on the PATH."""
    try:
        import imageio_ffmpeg

        return imageio_ffmpeg.get_ffmpeg_exe()
    except (ImportError, RuntimeError):
        return shutil.which("ffmpeg")


def check_video_path(path: Path) -> None:
    """Refuse, before anything runs, a video that could not be written at the end."""
    suffix = path.suffix.lower()
    if suffix not in FORMATS:
        raise VideoError(f"--video {path}: name the file *.gif or *.mp4")
    if suffix == ".mp4" and mp4_encoder() is None:
        raise VideoError(f"--video {path}: MP4 needs ffmpeg, and none is installed; "
                         "pip install 'atd[video]', or name the file *.gif")
    if not path.parent.is_dir():
        raise VideoError(f"--video {path}: the folder {path.parent} does not exist")


def write_mp4(path: Path, frames: list[np.ndarray], frame_period: float = FRAME_PERIOD) -> None:
    """Encode RGB frames (h, w, 3; even sizes) as H.264 in MP4, atomically; OSError when the
    file system refuses it (full, over a size limit, read-only), VideoError when ffmpeg fails otherwise."""
    height, width = frames[0].shape[:2]
    frames_in = b"".join(np.ascontiguousarray(f).tobytes() for f in frames)
    with replacing(path) as tmp:
        command = [mp4_encoder(), "-y", "-loglevel", "error", "-f", "rawvideo", "-pix_fmt", "rgb24",
                   "-s", f"{width}x{height}", "-r", f"{1 / frame_period:g}", "-i", "-",
                   "-c:v", "libx264", "-pix_fmt", "yuv420p", "-f", "mp4", str(tmp)]
        # restore_signals=False: ffmpeg keeps SIGXFSZ ignored, as here, so a file-size limit is
        # an error it reports (EFBIG) rather than a signal that kills it without a word.
        done = subprocess.run(command, input=frames_in, capture_output=True, restore_signals=False)
        if done.returncode != 0:
            said = done.stderr.decode(errors="replace").strip()
            write_error = next((code for code in _WRITE_ERRORS if os.strerror(code) in said), None)
            if write_error is not None:
                raise OSError(write_error, os.strerror(write_error))
            raise VideoError(f"ffmpeg could not write {path}: {said}")


class Recorder:
    """Called every control tick; keeps a frame every `FRAME_PERIOD` of simulated time."""

    def __init__(self) -> None:
        self.frames: list[np.ndarray] = []
        self.error: str | None = None  # why rendering failed, if it did: recording then stops
        self._next = 0.0

    def __call__(self, robot) -> None:
        now = robot.read().time
        if self.error is None and now >= self._next:
            try:
                self.frames.append(robot.render(WIDTH, HEIGHT))
            except Exception as exc:  # no OpenGL context, or no display: report, keep simulating
                self.error = f"{type(exc).__name__}: {exc}"
            self._next = now + FRAME_PERIOD

    def save(self, path: Path) -> str:
        """Write the frames as `path`'s format says; what became of the video, for the user."""
        if self.error or not self.frames:
            return (f"no video written to {path}: offscreen rendering failed ({self.error or 'no frames'}); "
                    "try MUJOCO_GL=egl or MUJOCO_GL=osmesa")
        try:
            (write_mp4 if path.suffix.lower() == ".mp4" else write_gif)(path, self.frames)
        except VideoError as exc:
            return f"no video written: {exc}"
        except OSError as exc:
            raise OutputError(describe_write_error(path, exc)) from None
        return f"video: {path} ({len(self.frames)} frames)"
