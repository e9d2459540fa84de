"""Convex parts of a concave OBJ mesh, because both engines collide a moving body's mesh
as its convex hull: a mug's hull is a closed can, and fingers would stop on its mouth.

V-HACD (`pybullet.vhacd`) splits a mesh once; its parts are kept under the user's cache
folder (`ATD_CACHE_DIR`, else `$XDG_CACHE_HOME/atd`, else `~/.cache/atd`), keyed by the
mesh file's content, so later runs and parallel workers reuse them.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

from atd.model.meshcheck import MeshError, mesh_points

VHACD_RESOLUTION = 100_000  # voxels: about 1 s for a mug, parts within a millimetre of its walls
_VHACD = "import sys, pybullet; pybullet.vhacd(*sys.argv[1:4], resolution=int(sys.argv[4]))"


def cache_dir() -> Path:
    """Where computed mesh data lives: never the repository, always safe to delete."""
    if os.environ.get("ATD_CACHE_DIR"):
        return Path(os.environ["ATD_CACHE_DIR"])
    xdg = os.environ.get("XDG_CACHE_HOME")
    return (Path(xdg) if xdg else Path.home() / ".cache") / "atd"


def convex_parts(mesh: Path) -> tuple[Path, ...]:
    """The mesh's convex parts as OBJ files in the mesh's own frame, computed on first use."""
    digest = hashlib.sha256(mesh.read_bytes()).hexdigest()[:20]
    folder = cache_dir() / "convex" / digest
    if not folder.is_dir():
        _decompose(mesh, folder)
    return tuple(sorted(folder.glob("part_*.obj")))


def _decompose(mesh: Path, folder: Path) -> None:
    """Split `mesh` into `folder`, atomically: a folder that exists is complete."""
    mesh_points(mesh)  # V-HACD would crash on a broken file
    folder.parent.mkdir(parents=True, exist_ok=True)
    work = Path(tempfile.mkdtemp(prefix=".tmp-", dir=folder.parent))
    try:
        hulls = work / "hulls.obj"
        # In a process of its own: V-HACD prints its progress to stdout and may crash on a bad mesh.
        done = subprocess.run([sys.executable, "-c", _VHACD, str(mesh), str(hulls), str(work / "vhacd.log"),
                               str(VHACD_RESOLUTION)], capture_output=True)
        vertices, parts = _hulls(hulls) if done.returncode == 0 and hulls.is_file() else (np.zeros((0, 3)), [])
        if not parts:
            raise MeshError(f"{mesh}: V-HACD found no convex parts (exit status {done.returncode}); "
                            "check that the file is a closed OBJ mesh")
        for k, faces in enumerate(parts):
            _write_part(work / f"part_{k:03d}.obj", vertices, faces)
        hulls.unlink()
        try:
            os.rename(work, folder)
        except OSError:  # another process finished first: its parts are as good as ours
            if not folder.is_dir():
                raise
    finally:
        shutil.rmtree(work, ignore_errors=True)


def _hulls(path: Path) -> tuple[np.ndarray, list[list[list[int]]]]:
    """V-HACD's output: its vertices, and the faces (0-based vertex indices) of each hull (`o`)."""
    vertices: list[list[float]] = []
    parts: list[list[list[int]]] = []
    for line in path.read_text().splitlines():
        words = line.split()
        if words and words[0] == "v":
            vertices.append([float(w) for w in words[1:4]])
        elif words and words[0] == "o":
            parts.append([])
        elif words and words[0] == "f" and parts:
            parts[-1].append([int(w.split("/")[0]) - 1 for w in words[1:]])
    return np.array(vertices), [p for p in parts if p]


def _write_part(path: Path, vertices: np.ndarray, faces: list[list[int]]) -> None:
    used = sorted({i for face in faces for i in face})
    new = {old: k + 1 for k, old in enumerate(used)}
    lines = [f"v {x:.9g} {y:.9g} {z:.9g}" for x, y, z in vertices[used]]
    lines += ["f " + " ".join(str(new[i]) for i in face) for face in faces]
    path.write_text("\n".join(lines) + "\n")
