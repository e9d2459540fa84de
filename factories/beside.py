"""Files a robot package keeps beside its factory: its `description.py` and `config.toml`.

A factory may live in any installed package, so both are found next to the module that
defines the factory class, or, when that folder has none, next to the class it extends
(a variant of a robot shares its body and its tuning), never in this project's own folders.
"""

from __future__ import annotations

import sys
from importlib import import_module
from pathlib import Path
from types import ModuleType


def _folders(factory: type) -> list[tuple[str, Path]]:
    """(package, folder) of each class in the factory's MRO that lives in a package, nearest first."""
    found: list[tuple[str, Path]] = []
    for cls in factory.__mro__:
        package = cls.__module__.rpartition(".")[0]
        file = getattr(sys.modules.get(cls.__module__), "__file__", None)
        if package and file and (package, Path(file).parent) not in found:
            found.append((package, Path(file).parent))
    return found


def description_module(factory: type) -> ModuleType:
    """The `description` module beside the factory's module, or beside the one it extends."""
    for package, folder in _folders(factory):
        if (folder / "description.py").is_file():
            module = import_module(f"{package}.description")
            if callable(getattr(module, "description", None)):
                return module
    raise LookupError(f"factory '{getattr(factory, 'name', factory.__name__)}' has no description.py beside it")


def shipped_config(factory: type) -> Path | None:
    """The `config.toml` beside the factory's module, or beside the one it extends; None without one."""
    return next((folder / "config.toml" for _, folder in _folders(factory) if (folder / "config.toml").is_file()), None)


def description_file(factory: type) -> str:
    """Where the factory's description lives, as a user would open it: relative to the
    working folder when it is inside it, absolute otherwise."""
    path = Path(description_module(factory).__file__).resolve()
    return str(path.relative_to(Path.cwd())) if path.is_relative_to(Path.cwd()) else str(path)
