"""A run's video as a file: frames with the state and the simulated time drawn on them,
encoded by a library: Pillow writes GIF, ffmpeg writes MP4 (the `video` extra brings one:
imageio-ffmpeg). `atd.sim.video_recorder` renders the frames.

A GIF frame is quantised at capture to the palette of the first frame (255 colours, one
left free): the scene's colours barely change during a run, so every frame shares one
global palette, and Pillow writes each frame after the first as its changed rectangle
with the unchanged pixels transparent, which is what keeps a run's GIF small.
"""

from __future__ import annotations

import errno
import functools
import io
import os
import re
import shutil
import subprocess
import tempfile
from pathlib import Path
import numpy as np
from PIL import Image, ImageDraw, ImageFont

from atd.sim.scene import WORKSPACE_CAMERA
from factories.description import RobotDescription

FORMATS = (".gif", ".mp4")
DEFAULT_SIZE = (640, 480)
SIZE_LIMITS = (64, 3840)  # pixels, each side: MP4's yuv420p also wants even sides
FRAME_PERIOD = 0.1  # s of simulated time between frames: what a video costs grows with the run, not the tick
# Failures of ffmpeg that are the file system's, reported like those of any other output.
_WRITE_ERRORS = (errno.ENOSPC, errno.EDQUOT, errno.EFBIG, errno.EACCES, errno.EROFS)


class VideoError(Exception):
    """The video cannot be written; the message says what to do instead."""


def parse_size(text: str) -> tuple[int, int]:
    """'640x480' as (640, 480); VideoError naming the accepted form otherwise."""
    low, high = SIZE_LIMITS
    match = re.fullmatch(r"\s*(\d{1,5})\s*[xX]\s*(\d{1,5})\s*", text)
    size = (int(match[1]), int(match[2])) if match else None
    if size is None or not all(low <= side <= high and side % 2 == 0 for side in size):
        raise VideoError(f"--video-size {text}: give WIDTHxHEIGHT in pixels, e.g. 640x480, "
                         f"each an even number from {low} to {high}")
    return size


def cameras(robot: RobotDescription) -> tuple[str, ...]:
    """The cameras a video of `robot` can be rendered from: the free one on the work area
    (the default), then the robot's described cameras."""
    return (WORKSPACE_CAMERA, *(c.name for c in robot.cameras))


def check_camera(camera: str, robot: RobotDescription) -> None:
    """Refuse a camera `robot` and its scene do not have, naming those they have."""
    if camera not in cameras(robot):
        raise VideoError(f"--camera {camera}: {robot.name} has no such camera; "
                         f"choose one of: {', '.join(cameras(robot))}")


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
                         "pip install 'atd-robotics[video]', or name the file *.gif")
    if not path.parent.is_dir():
        raise VideoError(f"--video {path}: the folder {path.parent} does not exist")


@functools.cache
def _font(size: int) -> ImageFont.FreeTypeFont | ImageFont.ImageFont:
    """Pillow's own font at `size` pixels (its bitmap font where Pillow has no FreeType), loaded once."""
    return ImageFont.load_default(size=size)


def draw_label(frame: np.ndarray, text: str) -> Image.Image:
    """The frame with `text` in white on a dark band at its top left."""
    image = Image.fromarray(frame)
    draw = ImageDraw.Draw(image)
    font = _font(max(10, image.height // 28))
    margin = max(4, image.height // 80)
    left, top, right, bottom = draw.textbbox((2 * margin, 2 * margin), text, font=font)
    draw.rectangle((margin, margin, right + margin, bottom + margin), fill=(20, 20, 24))
    draw.text((2 * margin, 2 * margin), text, font=font, fill=(255, 255, 255))
    return image


def encode_gif(frames: list[Image.Image], frame_period: float = FRAME_PERIOD) -> bytes:
    """Palette frames sharing one palette as a looping GIF."""
    out = io.BytesIO()
    frames[0].save(out, format="GIF", save_all=True, append_images=frames[1:], loop=0, optimize=True,
                   duration=round(frame_period * 1000), palette=frames[0].getpalette())
    return out.getvalue()


def encode_mp4(frames: list[np.ndarray], folder: Path, frame_period: float = FRAME_PERIOD) -> bytes:
    """RGB frames (h, w, 3; even sizes) as H.264 in MP4, by way of a temporary file in
    `folder` (where the video goes, so that the file system that refuses it is that one's);
    OSError when it is refused (full, over a size limit), VideoError when ffmpeg fails otherwise."""
    height, width = frames[0].shape[:2]
    frames_in = b"".join(np.ascontiguousarray(f).tobytes() for f in frames)
    with tempfile.TemporaryDirectory(prefix=".atd-video-", dir=folder) as work:
        encoded = Path(work) / "video.mp4"  # MP4 puts its index at the end: ffmpeg seeks, so no pipe
        command = [mp4_encoder(), "-y", "-loglevel", "error", "-f", "rawvideo", "-pix_fmt", "rgb24",
                   "-s", f"{width}x{height}", "-r", f"{1 / frame_period:g}", "-i", "-",
                   "-c:v", "libx264", "-pix_fmt", "yuv420p", "-f", "mp4", str(encoded)]
        # restore_signals=False: ffmpeg keeps SIGXFSZ ignored, as here, so a file-size limit is
        # an error it reports (EFBIG) rather than a signal that kills it without a word.
        done = subprocess.run(command, input=frames_in, capture_output=True, restore_signals=False)
        if done.returncode != 0:
            said = done.stderr.decode(errors="replace").strip()
            write_error = next((code for code in _WRITE_ERRORS if os.strerror(code) in said), None)
            if write_error is not None:
                raise OSError(write_error, os.strerror(write_error))
            raise VideoError(f"ffmpeg could not encode the video: {said}")
        return encoded.read_bytes()


class Frames:
    """The frames of one video as they are rendered, each labelled; `encode` makes them the
    file the path names. For an MP4 it keeps RGB frames; for a GIF, frames already
    quantised (a third of the memory)."""

    def __init__(self, path: Path, size: tuple[int, int], camera: str) -> None:
        self.path, self.size, self.camera = path, size, camera
        self.mp4 = path.suffix.lower() == ".mp4"
        self.frames: list = []
        self._palette: Image.Image | None = None

    def add(self, rendered: np.ndarray, sim_time: float, state: str) -> None:
        """One frame, with the simulated time and the state (if any) drawn on it."""
        image = draw_label(rendered, f"{sim_time:6.2f} s  {state}" if state else f"{sim_time:6.2f} s")
        if self.mp4:
            self.frames.append(np.asarray(image))
        elif self._palette is None:
            self._palette = image.quantize(255, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE)
            self.frames.append(self._palette)
        else:
            self.frames.append(image.quantize(palette=self._palette, dither=Image.Dither.NONE))

    def encode(self) -> bytes:
        """The file's bytes, in the format the path names (VideoError, OSError: see `encode_mp4`)."""
        return encode_mp4(self.frames, self.path.parent) if self.mp4 else encode_gif(self.frames)
