"""What a campaign spec's schema cannot know: that its task files are tasks that validate,
its robots, arms and objects exist, and that no two entries make the same cell.

Two entries making one cell would run its trials twice under one name: the store keeps
one, the other stops the campaign or is skipped by `--resume`, and a rate counts what it
should not. Read from the raw TOML, so all of it is found together with the schema's own
errors; entries of the wrong type are the schema's to report.
"""

from __future__ import annotations

import re
from pathlib import Path

from atd.campaign.record import TASK_OBJECT
from atd.model import has_errors, load_task
from atd.model.diagnostics import Diagnostic, Severity, did_you_mean, error
from atd.model.files import real_path, unreadable
from atd.model.task import Location
from atd.model.toml_lines import TomlLines

#: A plain name: a perturbation's becomes part of cell keys and recording file names.
PLAIN_NAME = re.compile(r"[A-Za-z0-9_.-]+")


def check_entries(data: dict, folder: Path, where: str, lines: TomlLines) -> list[Diagnostic]:
    """Every problem of the spec's entries, located in the spec (and a task's own errors,
    located in the task)."""
    return [*_tasks(data, folder, where, lines), *_robots(data, where, lines), *_objects(data, where, lines),
            *_needs_pybullet(data, where, lines),
            *(d for key in ("engines", "grasps", "objects") for d in _repeated(data, key, where, lines)),
            *_perturbation_names(data, where, lines), *_perturbation_objects(data, where, lines),
            *_fixtures(data, where, lines)]


def _tasks(data: dict, folder: Path, where: str, lines: TomlLines) -> list[Diagnostic]:
    """Each task a regular file that validates, and each making cells of its own name (its
    file's stem): `a/lift.xml` and `b/lift.xml` would both make cells named 'lift'."""
    found = []
    named: dict[str, Path] = {}  # cell name -> the task file that makes it
    for i, entry in _entries(data, "tasks"):
        file = entry.get("file") if isinstance(entry, dict) else entry
        if not isinstance(file, str):
            continue
        at = lines.find(("tasks", i), where)
        path = real_path(folder / file)
        problem = unreadable(path)
        if problem:
            found.append(error("CMP020", f"task {path}: {problem}", at, "task files are relative to the spec"))
            continue
        first = named.get(path.stem)
        if first is None:
            named[path.stem] = path
            found += _invalid(path, at)
        elif first == path:
            found.append(error("CMP024", f"task {file} is listed twice", at, "list each task once"))
        else:
            found.append(error("CMP025", f"tasks {first} and {path} would both make cells named '{path.stem}'",
                               at, "a cell is named after its task file: rename one of them"))
    return found


def _invalid(path: Path, at: Location) -> list[Diagnostic]:
    """A task that does not validate, with its own errors: every trial of it would be an error."""
    found = load_task(path)[1]
    if not has_errors(found):
        return []
    return [error("CMP026", f"task {path} does not validate (its errors are listed below)", at,
                  f"fix it; `atd validate {path}` checks it alone"),
            *(d for d in found if d.severity is Severity.ERROR)]


def _robots(data: dict, where: str, lines: TomlLines) -> list[Diagnostic]:
    """Each robot installed, each arm one of its own, each (robot, arm) once; no arms
    listed means the robot's first."""
    from factories.registry import installed

    found = []
    robots = installed()
    taken: set[tuple[str, str]] = set()
    for i, entry in _entries(data, "robots"):
        name = entry.get("name") if isinstance(entry, dict) else entry
        if not isinstance(name, str):
            continue
        at = lines.find(("robots", i), where)
        if name not in robots:
            found.append(error("CMP021", f"no robot '{name}' is installed", at,
                               did_you_mean(name, robots) or f"installed: {', '.join(robots)}"))
            continue
        arms = [a.name for a in robots[name].load().arms]
        listed = entry.get("arms", []) if isinstance(entry, dict) else []
        if not isinstance(listed, list):
            continue
        for arm in [a for a in listed if isinstance(a, str)] or arms[:1]:
            if arm not in arms:
                found.append(error("CMP022", f"robot '{name}' has no arm '{arm}'",
                                   lines.find(("robots", i, "arms"), where), f"its arms: {', '.join(arms)}"))
            elif (name, arm) in taken:
                found.append(error("CMP024", f"robot '{name}' with arm '{arm}' is listed twice", at,
                                   "list each robot and arm once (no arms listed: its first arm)"))
            taken.add((name, arm))
    return found


def _objects(data: dict, where: str, lines: TomlLines) -> list[Diagnostic]:
    named = [(i, o) for i, o in _entries(data, "objects") if isinstance(o, str) and o != TASK_OBJECT]
    if not named:
        return []
    from atd.campaign.objects import library

    known = library()
    return [error("CMP023", f"no object '{name}' in the library", lines.find(("objects", i), where),
                  did_you_mean(name, known) or f"'{TASK_OBJECT}' or one of: {', '.join(known)}")
            for i, name in named if name not in known]


def _needs_pybullet(data: dict, where: str, lines: TomlLines) -> list[Diagnostic]:
    """The PyBullet engine and the library's meshes, asked for where PyBullet is not installed
    (it is optional: atd/sim/optional.py)."""
    from atd.sim.library import library
    from atd.sim.optional import pybullet_installed, pybullet_missing

    if pybullet_installed():
        return []
    known = library()
    world = data.get("world") if isinstance(data.get("world"), dict) else {}
    named = [(("objects", i), name) for i, name in _entries(data, "objects")]
    named += [(("world", "from", i), name) for i, name in _entries(world, "from")]
    engines = [error("CMP029", pybullet_missing("the pybullet engine"), lines.find(("engines", i), where),
                     "or leave 'pybullet' out")
               for i, engine in _entries(data, "engines") if engine == "pybullet"]
    meshes = [error("CMP029", known[name].unavailable, lines.find(loc, where), "or use an object without a mesh")
              for loc, name in named if isinstance(name, str) and name in known and known[name].unavailable]
    return engines + meshes


def _repeated(data: dict, key: str, where: str, lines: TomlLines) -> list[Diagnostic]:
    seen: set[str] = set()
    found = []
    for i, value in _entries(data, key):
        if not isinstance(value, str):
            continue
        if value in seen:
            found.append(error("CMP024", f"{key} lists '{value}' twice", lines.find((key, i), where),
                               f"list each of the {key} once"))
        seen.add(value)
    return found


def _perturbation_names(data: dict, where: str, lines: TomlLines) -> list[Diagnostic]:
    table = data.get("perturbations")
    names = table if isinstance(table, dict) else {}
    return [error("CMP027", f"perturbation name '{name}' is not a plain name", lines.find(("perturbations", name), where),
                  "use letters, digits, '_', '.' and '-': the name is part of each cell's name and recording")
            for name in names if not PLAIN_NAME.fullmatch(name)]


def _perturbation_objects(data: dict, where: str, lines: TomlLines) -> list[Diagnostic]:
    """A perturbation tried on some objects names only objects the spec lists: another would
    make no cell, and the perturbation would silently be tried on nothing."""
    table = data.get("perturbations")
    listed = [o for _, o in _entries(data, "objects")] or [TASK_OBJECT]
    found = []
    for name, model in (table.items() if isinstance(table, dict) else ()):
        objects = model.get("objects") if isinstance(model, dict) else None
        for i, obj in enumerate(objects if isinstance(objects, list) else ()):
            if isinstance(obj, str) and obj not in listed:
                found.append(error("CMP023", f"perturbation '{name}' is tried on object '{obj}', which the spec's "
                                             "objects do not list", lines.find(("perturbations", name, "objects"), where),
                                   did_you_mean(obj, listed) or f"the spec's objects: {', '.join(listed)}"))
    return found


def _fixtures(data: dict, where: str, lines: TomlLines) -> list[Diagnostic]:
    """A task whose objects stand in a fixture is tried only on screw-capped objects: a
    clamp holds a bottle or jar by its neck, and nothing else has one."""
    from atd.campaign.objects import library

    known = library()
    found = []
    for i, entry in _entries(data, "tasks"):
        if not (isinstance(entry, dict) and entry.get("fixture") is True):
            continue
        for obj in (o for _, o in _entries(data, "objects") or [(0, TASK_OBJECT)]):
            if isinstance(obj, str) and (obj == TASK_OBJECT or (obj in known and known[obj].thread is None)):
                found.append(error("CMP028", f"task {entry.get('file')} stands its objects in a fixture, but "
                                             f"'{obj}' has no screw cap", lines.find(("tasks", i), where),
                                   "list only screw-capped library objects (docs/objects.md), or drop fixture"))
    return found


def _entries(data: dict, key: str) -> list[tuple[int, object]]:
    value = data.get(key)
    return list(enumerate(value)) if isinstance(value, list) else []
