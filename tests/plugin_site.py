"""A robot distribution from another package, laid out as pip installs a wheel: a package
and a .dist-info declaring its `atd.factories` entry point, in a site folder of its own.
Putting the folder on sys.path (or PYTHONPATH) installs it; nothing is built or copied."""

from __future__ import annotations

import textwrap
from pathlib import Path


def write_robot_package(site: Path, name: str, config: str = "") -> Path:
    """A Melfa twin called `name` with its own description.py and config.toml; returns its package folder."""
    package = site / f"atd_{name}"
    package.mkdir(parents=True)
    (package / "__init__.py").write_text("")
    (package / "factory.py").write_text(textwrap.dedent(f'''\
        from factories.melfa.factory import MelfaFactory

        class TwinFactory(MelfaFactory):
            name = "{name}"
            description = "a Melfa twin from another package"
        '''))
    (package / "description.py").write_text(textwrap.dedent(f'''\
        from dataclasses import replace

        from factories.melfa.description import description as melfa

        def description(arm=None):
            return replace(melfa(arm), name="{name}")
        '''))
    (package / "config.toml").write_text(config)
    register_robot(site, name, f"atd_{name}.factory:TwinFactory")
    return package


def register_robot(site: Path, name: str, target: str) -> None:
    """Declare the robot `name` = `target` ("module:Class") in a .dist-info in `site`, as pip would."""
    info = site / f"atd_{name}-0.1.dist-info"
    info.mkdir(parents=True)
    (info / "METADATA").write_text(f"Metadata-Version: 2.1\nName: atd-{name}\nVersion: 0.1\n")
    (info / "entry_points.txt").write_text(f"[atd.factories]\n{name} = {target}\n")
