"""Recording a run as an animated GIF, with no imaging package.

The GIF is written with an uncompressed LZW stream (a clear code every 254 pixels keeps
the code width at 9 bits): larger files than a real encoder makes, but a few lines of
numpy and readable by every viewer. Frames use a fixed 3-3-2 bit colour palette.
"""

from __future__ import annotations

import os
import struct
import tempfile
from pathlib import Path

import numpy as np

WIDTH, HEIGHT = 320, 240
FRAME_PERIOD = 0.1  # s of simulated time between frames
_CLEAR, _END = 256, 257
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
    fd, tmp = tempfile.mkstemp(dir=path.parent, suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(b"".join(out))
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        os.unlink(tmp)
        raise


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
