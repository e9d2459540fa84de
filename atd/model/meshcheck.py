"""Checking a mesh file before any physics engine reads it.

Both engines trust their mesh loaders with whatever file they are given: a text file named
.stl segfaults PyBullet, a garbage .obj hangs or crashes it and raises in MuJoCo. So the
validator and the scene builder read the mesh here first, with the input guard, and accept
it only when it is a readable STL (binary or ASCII) or OBJ whose vertices are finite and
span a solid (not all on one plane), at a size the world can hold.
"""

from __future__ import annotations

import re
import struct
from functools import lru_cache
from pathlib import Path

import numpy as np

import atd.model.ranges as ranges
from atd.model.files import InputError, read_capped

SUFFIXES = (".stl", ".obj")
MAX_BYTES = 64 * 1024 * 1024  # a detailed scanned object is a few MB
FLATNESS = 1e-9  # m: thinner than this in some direction and the engines cannot give it a volume
MIN_AREA = 1e-12  # m^2 of surface: MuJoCo refuses a mesh whose surface is (near) nothing

_ASCII_VERTEX = re.compile(rb"^\s*vertex\s+(\S+)\s+(\S+)\s+(\S+)", re.M)
_STL_RECORD = np.dtype([("normal", "<f4", 3), ("vertices", "<f4", (3, 3)), ("attribute", "<u2")])


class MeshError(ValueError):
    """A mesh no engine should be given; the message says what is wrong with the file."""


def check_mesh(path: Path, scale: tuple[float, float, float] = (1.0, 1.0, 1.0)) -> np.ndarray:
    """The mesh's triangles (n x 3 x 3 corners) scaled along its axes (a URDF may draw a
    mesh in millimetres at scale 0.001), or MeshError saying why the file cannot be simulated."""
    vertices, faces = read_mesh(path, scale)
    return vertices[faces]


def read_mesh(path: Path, scale: tuple[float, float, float] = (1.0, 1.0, 1.0)) -> tuple[np.ndarray, np.ndarray]:
    """The mesh's vertices (n x 3, scaled) and triangles (m x 3 vertex indices), every object
    of an OBJ file in one, once checked as `check_mesh` checks them. Read-only arrays, read
    once per process while the file is unchanged: a robot's visual meshes are megabytes of
    text, wanted by its description and again by each model built from it."""
    suffix = path.suffix.lower()
    if suffix not in SUFFIXES:
        raise MeshError(f"{suffix or 'no suffix'} meshes are not supported; use an STL or OBJ file")
    try:
        info = path.stat()
        version = info.st_mtime_ns, info.st_size
    except OSError:  # reading it says why
        version = 0, 0
    return _read_mesh(path, *version, tuple(float(v) for v in scale))


@lru_cache(maxsize=256)
def _read_mesh(path: Path, mtime_ns: int, size: int, scale: tuple[float, ...]) -> tuple[np.ndarray, np.ndarray]:
    try:
        data = read_capped(path, MAX_BYTES)
    except InputError as exc:
        raise MeshError(str(exc)) from None
    vertices, faces = _stl_mesh(data) if path.suffix.lower() == ".stl" else _obj_mesh(data)
    vertices = vertices * np.asarray(scale, float)
    _check_solid(vertices[faces])
    vertices.flags.writeable = faces.flags.writeable = False
    return vertices, faces


def mesh_points(path: Path, scale: tuple[float, float, float] = (1.0, 1.0, 1.0)) -> np.ndarray:
    """Every corner of the mesh's triangles, scaled, one row each; MeshError naming the file
    when it cannot be simulated."""
    try:
        return check_mesh(path, scale).reshape(-1, 3)
    except MeshError as exc:
        raise MeshError(f"{path}: {exc}") from None


def _numbers(words: list[bytes]) -> list[float]:
    """Coordinates as an engine's mesh loader reads them: float() alone would take '1_0' for 10."""
    numbers = []
    for word in words:
        try:
            if b"_" in word:
                raise ValueError
            numbers.append(float(word))
        except ValueError:
            raise MeshError(f"'{_shown(word)}' is not a number") from None
    return numbers


def _index(word: bytes) -> int:
    """A vertex number in ASCII digits, with a sign for counting from the end."""
    if word.isdigit() or (word[:1] in (b"-", b"+") and word[1:].isdigit()):
        return int(word)
    raise MeshError(f"'{_shown(word)}' is not a vertex number")


def _shown(word: bytes) -> str:
    """A word from a file that may be binary, fit to print."""
    return "".join(c if c.isprintable() else "?" for c in word[:20].decode(errors="replace"))


def _stl_mesh(data: bytes) -> tuple[np.ndarray, np.ndarray]:
    """An STL's corners as vertices, three a triangle (STL shares none)."""
    triangles = _stl_triangles(data)
    return triangles.reshape(-1, 3), np.arange(3 * len(triangles)).reshape(-1, 3)


def _stl_triangles(data: bytes) -> np.ndarray:
    if len(data) >= 84:
        (count,) = struct.unpack_from("<I", data, 80)
        if 84 + 50 * count == len(data):
            if count == 0:
                raise MeshError("the STL file has no triangles")
            records = np.frombuffer(data, _STL_RECORD, count, offset=84)
            return records["vertices"].astype(float)
    if not data.lstrip().startswith(b"solid"):
        raise MeshError("not an STL file: neither binary STL (its size does not match its triangle count) "
                        "nor ASCII STL (it does not start with 'solid')")
    vertices = []
    for m in _ASCII_VERTEX.finditer(data):
        try:
            vertices.append(_numbers(list(m.groups())))
        except MeshError as exc:
            line = data.count(b"\n", 0, m.start()) + 1  # counted only for the report
            raise MeshError(f"line {line}: {exc}") from None
    if not vertices or len(vertices) % 3:
        raise MeshError(f"the ASCII STL has {len(vertices)} vertices, not whole triangles of 3")
    return np.asarray(vertices, dtype=float).reshape(-1, 3, 3)


def _obj_mesh(data: bytes) -> tuple[np.ndarray, np.ndarray]:
    vertices: list[list[float]] = []
    corners: list[int] = []  # three vertex indices per triangle, each face split into a fan
    for number, line in enumerate(data.splitlines(), 1):
        try:
            _obj_statement(line.split(), vertices, corners)
        except MeshError as exc:
            raise MeshError(f"line {number}: {exc}") from None
    if not corners:
        raise MeshError("the OBJ file has no faces")
    return np.asarray(vertices, dtype=float), np.asarray(corners, dtype=np.intp).reshape(-1, 3)


def _obj_statement(words: list[bytes], vertices: list[list[float]], corners: list[int]) -> None:
    """One line of an OBJ file: a vertex or a face (split into a fan of triangles) is added,
    what draws nothing is passed over, anything else is refused."""
    if not words:
        return
    if words[0] == b"v":
        if len(words) < 4:
            raise MeshError("a vertex needs x y z")
        vertices.append(_numbers(words[1:4]))
    elif words[0] == b"f":
        if len(words) < 4:
            raise MeshError("a face needs at least 3 vertices")
        face = []
        for word in words[1:]:
            index = _index(word.split(b"/")[0])
            if index == 0 or abs(index) > len(vertices):
                raise MeshError(f"face vertex {index} does not exist ({len(vertices)} vertices so far)")
            face.append(index - 1 if index > 0 else len(vertices) + index)
        for i in range(1, len(face) - 1):
            corners += (face[0], face[i], face[i + 1])
    elif words[0] not in (b"#", b"vn", b"vt", b"vp", b"o", b"g", b"s", b"usemtl", b"mtllib", b"l") \
            and not words[0].startswith(b"#"):
        raise MeshError(f"'{_shown(words[0])}' is not an OBJ statement")


def _check_solid(triangles: np.ndarray) -> None:
    if not np.isfinite(triangles).all():
        raise MeshError("a vertex has a coordinate that is not a finite number")
    corners = triangles.reshape(-1, 3)
    problem = ranges.SIZE.problem(float((corners.max(axis=0) - corners.min(axis=0)).max()))
    if problem:
        raise MeshError(f"the mesh's largest extent: {problem}; meshes are in metres")
    area = 0.5 * np.linalg.norm(np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0]),
                                axis=1).sum()
    thinnest = np.linalg.svd(corners - corners.mean(axis=0), compute_uv=False)[-1] / np.sqrt(len(corners))
    if area < MIN_AREA or thinnest < FLATNESS:
        raise MeshError("the mesh is degenerate: its triangles have no area or lie on one plane, so it has no volume")
