"""`atd robots new`: a robot package that installs and runs as generated, to be made into
one's own robot by editing its numbers.

The files come from the templates beside this module; the whole package is written into a
hidden folder beside the target and renamed into place, so a failure leaves nothing behind.
"""

from __future__ import annotations

import os
import re
import shutil
import tempfile
from pathlib import Path

import jinja2

from atd.model.files import describe_write_error, name_too_long
from atd.scaffold.from_urdf import UrdfScaffoldError, urdf_values
from atd.scaffold.source import SourceError, identifier, literal

HANDS = ("parallel_jaw", "multi_finger")
NAME = re.compile(r"[a-z][a-z0-9_]{0,31}")


class ScaffoldError(ValueError):
    """Why the package cannot be written, in one line with the fix."""


_ENV = jinja2.Environment(loader=jinja2.PackageLoader("atd.scaffold", "templates"),
                          undefined=jinja2.StrictUndefined, keep_trailing_newline=True,
                          trim_blocks=True, lstrip_blocks=True)
# Every value read from input is written as a literal, `{{ value | py }}`, or as a checked name.
_ENV.filters["py"] = literal
_ENV.filters["identifier"] = identifier


def check_name(name: str, taken: list[str]) -> None:
    """A robot's name is also its package's (atd_NAME) and its entry point's: it must suit
    all three, and not hide an installed robot."""
    if not NAME.fullmatch(name):
        raise ScaffoldError(f"'{name}' cannot name a robot: use a lower-case letter, then up to 31 lower-case "
                            "letters, digits or '_' (it becomes a Python package name)")
    if name in taken:
        raise ScaffoldError(f"a robot '{name}' is already installed; choose another name")


def package_files(name: str, hand: str, urdf: Path | None = None) -> dict[str, str]:
    """Path inside the package folder -> text, for a robot `name` with a `hand` of HANDS,
    its body built in Python or, with `urdf`, read from that URDF: UrdfScaffoldError when
    the URDF cannot be imported, ScaffoldError for the rest."""
    package = f"atd_{name}"
    values: dict[str, object] = {"name": name, "hand": hand, "package": package, "dof": 6,
                                 "urdf_option": " --from-urdf URDF" if urdf else "", "urdf_package": "", "urdf_path": "",
                                 "cls": "".join(part.capitalize() for part in name.split("_")) + "Factory"}
    if urdf is not None:
        if hand != "parallel_jaw":
            raise ScaffoldError("--from-urdf makes a parallel-jaw robot (--hand parallel_jaw): a multi-finger hand's "
                                "DOFs and postures are not in a URDF; describe it by hand (docs/writing-a-robot.md)")
        values |= urdf_values(urdf, name)
    files = {
        "pyproject.toml": "pyproject.toml.j2",
        "README.md": "README.md.j2",
        f"{package}/__init__.py": "__init__.py.j2",
        f"{package}/description.py": "description_urdf.py.j2" if urdf else "description.py.j2",
        f"{package}/factory.py": "factory.py.j2",
        f"{package}/config.toml": "config.toml.j2",
        f"tests/test_{name}.py": "test_robot.py.j2",
        "tests/pick_and_place.xml": "pick_and_place.xml.j2",
    }
    try:
        return {path: _ENV.get_template(template).render(values) for path, template in files.items()}
    except SourceError as exc:
        raise UrdfScaffoldError(f"{urdf}: cannot write the description: {exc}; check the URDF's numbers") from None


def write_package(target: Path, files: dict[str, str]) -> None:
    """Create the folder `target` holding `files`, all at once; ScaffoldError when it cannot."""
    problem = name_too_long(target)
    if problem:
        raise ScaffoldError(f"cannot write {target}: {problem}")
    if target.exists() or target.is_symlink():
        raise ScaffoldError(f"{target} already exists; give -o a new folder, or remove it first")
    if not target.parent.is_dir():
        raise ScaffoldError(f"the folder {target.parent} does not exist; create it or give -o elsewhere")
    try:
        staging = Path(tempfile.mkdtemp(prefix=f".{target.name}.", dir=target.parent))
    except OSError as exc:
        raise ScaffoldError(describe_write_error(target, exc)) from None
    try:
        for path, text in files.items():
            (staging / path).parent.mkdir(parents=True, exist_ok=True)
            (staging / path).write_text(text, encoding="utf-8")
        os.chmod(staging, 0o777 & ~_umask())
        os.rename(staging, target)
    except OSError as exc:
        shutil.rmtree(staging, ignore_errors=True)
        raise ScaffoldError(describe_write_error(target, exc)) from None


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask
