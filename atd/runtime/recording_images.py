"""The depth camera in a recording: each picture a perceive state took, as the robot saw it,
on `/camera/depth` (`foxglove.RawImage`, 32-bit float metres, 0 where nothing was seen) and
the points it makes through the camera's believed pose on `/camera/points`
(`foxglove.PointCloud`, world frame). Pictures are taken on demand, not each tick, so they
are written when taken, not sampled with the rows. The JSON Schemas follow Foxglove's schema
reference (JSON encoding: times as {sec, nsec}, bytes as base64), so Foxglove's Image and 3D
panels show them as they are.
"""

from __future__ import annotations

import base64
from typing import Any, Iterator

import numpy as np

from atd.runtime.recording_scene import ROOT
from primitives.robot import DepthImage, point_cloud

DEPTH, POINTS = "/camera/depth", "/camera/points"
FLOAT32 = 7  # foxglove.NumericType of a 4-byte float
_TIME = {"type": "object", "properties": {"sec": {"type": "integer"}, "nsec": {"type": "integer"}}}
_BYTES = {"type": "string", "contentEncoding": "base64"}
_XYZ = {"type": "object", "properties": {a: {"type": "number"} for a in "xyz"}}
_XYZW = {"type": "object", "properties": {a: {"type": "number"} for a in "xyzw"}}
SCHEMAS: dict[str, dict[str, Any]] = {
    "foxglove.RawImage": {"type": "object", "title": "foxglove.RawImage", "properties": {
        "timestamp": _TIME, "frame_id": {"type": "string"}, "width": {"type": "integer"},
        "height": {"type": "integer"}, "encoding": {"type": "string"}, "step": {"type": "integer"}, "data": _BYTES}},
    "foxglove.PointCloud": {"type": "object", "title": "foxglove.PointCloud", "properties": {
        "timestamp": _TIME, "frame_id": {"type": "string"},
        "pose": {"type": "object", "properties": {"position": _XYZ, "orientation": _XYZW}},
        "point_stride": {"type": "integer"},
        "fields": {"type": "array", "items": {"type": "object", "properties": {
            "name": {"type": "string"}, "offset": {"type": "integer"}, "type": {"type": "integer"}}}},
        "data": _BYTES}},
}
#: topic, schema, ground truth
CHANNELS = ((DEPTH, "foxglove.RawImage", False), (POINTS, "foxglove.PointCloud", False))


def image_messages(image: DepthImage, zero: int = 0) -> Iterator[tuple[str, int, dict[str, Any]]]:
    """(topic, simulated time in ns, message) of one picture: the depth image, then its points,
    their timestamps `zero` ns (the run's wall clock at simulated 0) later."""
    ns = round(image.time * 1e9)
    stamp = {"sec": (zero + ns) // 1_000_000_000, "nsec": (zero + ns) % 1_000_000_000}
    depth = np.ascontiguousarray(image.depth, dtype="<f4")
    height, width = depth.shape
    yield DEPTH, ns, {"timestamp": stamp, "frame_id": image.sensor, "width": width, "height": height,
                      "encoding": "32FC1", "step": 4 * width, "data": base64.b64encode(depth.tobytes()).decode()}
    points = np.ascontiguousarray(point_cloud(image), dtype="<f4")
    yield POINTS, ns, {"timestamp": stamp, "frame_id": ROOT,
                       "pose": {"position": {"x": 0.0, "y": 0.0, "z": 0.0},
                                "orientation": {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0}},
                       "point_stride": 12, "fields": [{"name": a, "offset": 4 * k, "type": FLOAT32}
                                                      for k, a in enumerate("xyz")],
                       "data": base64.b64encode(points.tobytes()).decode()}
