"""The extras, here rather than in pyproject.toml: the `test` extra installs the Panda of
plugins/panda, and PEP 508 names a local package only by an absolute file URL, which is
computed here at build time. Everything else is declared in pyproject.toml."""

from pathlib import Path

from setuptools import setup

# Not "atd-panda": pip caches a wheel built from a folder whose name reads as name-version and
# reuses it for the same path, so a clone at a fixed path would install a stale Panda.
PANDA = Path(__file__).resolve().parent / "plugins" / "panda"
# imageio-ffmpeg ships an ffmpeg binary as a wheel: MP4 needs an H.264 encoder, which no one should write by hand.
VIDEO = ["imageio-ffmpeg>=0.5"]
# PyBullet, the second engine, and `pybullet_data`'s meshes (mug, duck, bunny, torus, jenga) and
# the Panda: PyPI has its wheels for CPython 3.11 only, so MuJoCo alone is the default install.
PYBULLET = ["pybullet>=3.2.6"]
# pytest-xdist spreads the suite over the machine's cores (2 on the CI machine).
TEST = ["pytest>=8", "pytest-xdist>=3.5", "hypothesis>=6.100"]
# Ray runs a campaign on a cluster (`atd campaign run --ray`); the local pool needs nothing extra.
RAY = ["ray>=2.9"]

setup(extras_require={
    "pybullet": PYBULLET,
    "video": VIDEO,
    "ray": RAY,
    "test": [*TEST, *PYBULLET, *VIDEO, *RAY, f"atd-panda @ {PANDA.as_uri()}"],
})
