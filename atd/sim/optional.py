"""PyBullet is an optional engine: PyPI has its wheels for CPython 3.11 only, so on 3.12 and
later pip would compile Bullet from source. MuJoCo runs every task without it; what needs it
(the PyBullet engine, the library's meshes from `pybullet_data`) says so, in the words below."""

from __future__ import annotations

from functools import cache
from importlib.util import find_spec

INSTALL = "pip install 'atd-robotics[pybullet]'"
WHY = "PyPI has PyBullet wheels for Python 3.11; on later Pythons pip builds it from source, with a C++ compiler"


@cache
def pybullet_installed() -> bool:
    """Whether `import pybullet` (and its `pybullet_data`) would work, without importing it."""
    return find_spec("pybullet") is not None


def pybullet_missing(what: str) -> str:
    """The one-line reason and fix for `what`, which needs PyBullet."""
    return f"{what} needs PyBullet, which is not installed; {INSTALL} ({WHY})"
