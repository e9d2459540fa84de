"""A world file: what is true on the table, whatever the task believes (thesis 3.4.3: the
robot knows the box, nothing of the five objects in it).

    [[container]]                 # an open box on the table: the true one when the task's differs
    name = "box"
    position = [0.15, 0.0]        # centre of its floor's underside; z optional (0: on the table)
    size = [0.30, 0.25, 0.10]     # outer lengths, m
    wall = 0.01                   # wall and floor thickness, m (default 0.01)

    [[object]]                    # placed: a library object, or a described shape
    library = "duck"              # or: shape = "box", size = [x, y, z], mass = 0.1, friction = 0.8
    name = "duck1"                # optional, unique
    position = [0.3, 0.2]         # z optional: resting on whatever is below
    rpy = [0, 0, 90]              # degrees, optional
    fixture = true                # optional: a screw-capped bottle held upright in a clamp on the table

    [[drop]]                      # dropped at random poses, seeded by the run's seed
    objects = ["duck", "mug", "ball", "stapler", "tape"]
    into = "box"                  # a container of this file or of the task
    clearance = 0.02              # optional, m: laid down resting, this far from the walls (below)

Read like an ATD: every problem at once, each located (file:line), with a code (WLD...) and
a hint. A world that lists objects replaces the task's; without any, the task's own stay.
The scene it makes asks to settle: the engine lets gravity bring every object to rest
before the run's clock starts (`SimRobot.settle`).

A drop with a `clearance` lays its objects down instead, as thesis 3.4.3 assumes its box was
filled ("some clearance between the objects and the sides of the box"): each resting (a
box on any face, a cylinder on an end or its side, an object with a mesh as the library stands
it) at a random turn about the vertical, its footprint that far from the walls and clear of
the others'. Dropped from above, a third of the objects come to rest within 5 mm of
a wall (`benchmarks/box_layout.py`).
"""

from __future__ import annotations

import dataclasses
import re
import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from atd.model import ranges
from atd.model.diagnostics import Diagnostic, did_you_mean, error, has_errors
from atd.model.files import InputError, read_capped
from atd.model.frames import rotation_rpy
from atd.model.task import Location
from atd.model.toml_lines import TomlLines
from atd.model.vocabulary import SIZE_LAYOUT, ObjectClass
from atd.sim.library import LibraryObject, library
from atd.sim.scene import (DEFAULT_FRICTION, DEFAULT_WEIGHT, TABLE_CENTRE, TABLE_HALF, Body, Container, Scene,
                           bounding_box, half_extent)

WORLD_CAP = 1 << 20  # bytes: a world file is a page of TOML
RPY = ranges.Range(-360.0, 360.0, "deg")
NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
DEFAULT_WALL = 0.01  # m, a cardboard box's
DROP_GAP = 0.01  # m between the bounding spheres of objects about to drop, and from the walls
OVERLAP = 0.001  # m that two placed objects' bounding boxes may share: they touch, they do not cut in
PLACES = 50  # places drawn for one object laid down before its layout is drawn again
LAYOUTS = 200  # layouts drawn before the box is called too full for the clearance
LAY_HEIGHT = 0.001  # m over the floor an object is laid at: it settles onto it without a bounce
_KEYS = {
    "object": ("library", "shape", "size", "mass", "friction", "name", "position", "rpy", "fixture"),
    "drop": ("objects", "into", "clearance"),
    "container": ("name", "position", "rpy", "size", "wall"),
}


class WorldError(ValueError):
    """The world file cannot be built into a scene; `diagnostics` say where and why."""

    def __init__(self, diagnostics: list[Diagnostic]) -> None:
        super().__init__("\n".join(d.render() for d in diagnostics))
        self.diagnostics = diagnostics


@dataclass(frozen=True)
class PlacedObject:
    """An object the file puts somewhere; where `rests`, its z is found when the scene is
    built: on top of whatever is below it."""

    body: Body
    rests: bool
    loc: Location
    named: bool  # the file gave its name (else it is called after what it is)


@dataclass(frozen=True)
class Drop:
    """Objects dropped into a container at random poses: (name in the world, library object);
    with a `clearance` (m), laid down resting that far from its walls instead."""

    objects: tuple[tuple[str, LibraryObject], ...]
    into: str
    loc: Location
    clearance: float = 0.0


@dataclass(frozen=True)
class World:
    """A world file, read: built into a scene once the task's belief is known."""

    objects: tuple[PlacedObject, ...]
    drops: tuple[Drop, ...]
    containers: tuple[tuple[Container, Location], ...]

    def scene(self, belief: Scene, seed: int) -> Scene:
        """The true scene: the believed one with this file's containers (replacing the task's
        of the same name) and objects (replacing the task's, when it lists any); the drops'
        poses drawn from `seed`. WorldError for what needs the belief to be found: a drop
        into a container neither names, objects that cut into each other."""
        found = [error("WLD023", f"'{name}' names an object here and a container of the task", loc,
                       "give the object another name")
                 for name, loc in [(p.body.name, p.loc) for p in self.objects]
                 + [(n, d.loc) for d in self.drops for n, _ in d.objects]
                 if name in {c.name for c in belief.containers}]
        mine = {c.name for c, _ in self.containers}
        containers = tuple(c for c in belief.containers if c.name not in mine) + tuple(c for c, _ in self.containers)
        fixed = [*belief.obstacles, *(part for c in containers for part in c.parts())]
        bodies = _rest(self.objects, fixed)
        found += _overlaps(bodies, self.objects, belief.obstacles)
        rng = np.random.default_rng([seed, 2])
        for drop in self.drops:
            box = next((c for c in containers if c.name == drop.into), None)
            if box is None:
                known = [c.name for c in containers]
                found.append(error("WLD024", f"no container '{drop.into}' to drop into", drop.loc,
                                   did_you_mean(drop.into, known) or
                                   f"add a [[container]] named '{drop.into}' (containers here: "
                                   f"{', '.join(known) or 'none'})"))
                continue
            try:
                bodies += (_laid(drop, box, rng) if drop.clearance else _dropped(drop, box, bodies, rng))
            except ValueError as exc:
                found.append(error("WLD025", str(exc), drop.loc, "use a larger container, or drop fewer objects"))
        if has_errors(found):
            raise WorldError(sorted(found, key=lambda d: d.loc.line))
        objects = tuple(bodies) if self.objects or self.drops else belief.objects
        return Scene(objects=objects, obstacles=belief.obstacles, table=belief.table, containers=containers,
                     settle=bool(self.objects or self.drops))


def load_world(path: Path) -> tuple[World | None, list[Diagnostic]]:
    """The world file, or None with every problem found in it."""
    where = str(path)
    try:
        text = read_capped(path, WORLD_CAP).decode("utf-8")
    except (InputError, UnicodeDecodeError) as exc:
        return None, [error("WLD001", f"cannot read the world file: {exc}", Location(where, 0),
                            "give a readable UTF-8 TOML file")]
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        line = int(m.group(1)) if (m := re.search(r"line (\d+)", str(exc))) else 0
        return None, [error("WLD002", f"not valid TOML: {exc}", Location(where, line), "fix the TOML syntax")]
    reader = _Reader(where, TomlLines(text))
    for key in data:
        if key not in _KEYS:
            reader.error("WLD010", f"unknown table '{key}'", (key,),
                         did_you_mean(key, _KEYS) or "a world file holds [[object]], [[drop]] and [[container]] tables")
    tables = {key: reader.tables(data, key) for key in _KEYS}
    containers = tuple(c for i, t in tables["container"] if (c := reader.container(i, t)) is not None)
    placed = [p for i, t in tables["object"] if (p := reader.placed(i, t)) is not None]
    drops = [d for i, t in tables["drop"] if (d := reader.drop(i, t)) is not None]
    placed, drops = _named(placed, drops, containers, reader)
    found = sorted(reader.found, key=lambda d: d.loc.line)
    if has_errors(found):
        return None, found
    return World(tuple(placed), tuple(drops), containers), found


class _Reader:
    """Reads the tables of one world file, collecting located diagnostics as it goes."""

    def __init__(self, where: str, lines: TomlLines) -> None:
        self.where, self.lines = where, lines
        self.found: list[Diagnostic] = []

    def at(self, loc: tuple) -> Location:
        return self.lines.find(loc, self.where)

    def error(self, code: str, message: str, loc: tuple, hint: str | None = None) -> None:
        self.found.append(error(code, message, self.at(loc), hint))

    def tables(self, data: dict, key: str) -> list[tuple[int, dict]]:
        """The entries of `[[key]]`, each checked for unknown keys."""
        value = data.get(key, [])
        if not isinstance(value, list) or not all(isinstance(t, dict) for t in value):
            self.error("WLD012", f"'{key}' must be a list of tables", (key,), f"write each one under [[{key}]]")
            return []
        for i, table in enumerate(value):
            for name in table:
                if name not in _KEYS[key]:
                    self.error("WLD010", f"unknown key '{name}' in [[{key}]]", (key, i, name),
                               did_you_mean(name, _KEYS[key]) or f"known keys here: {', '.join(_KEYS[key])}")
        return list(enumerate(value))

    def numbers(self, table: dict, loc: tuple, counts: tuple[int, ...], allowed: ranges.Range,
                required: bool = False) -> tuple[float, ...] | None:
        """A list of `counts` numbers, each in `allowed`; None (reported) when it is not one."""
        value = table.get(loc[-1])
        if value is None:
            if required:
                self.error("WLD011", f"[[{loc[0]}]] needs '{loc[-1]}'", loc[:-1], f"add {loc[-1]} = [...]")
            return None
        wanted = " or ".join(str(n) for n in counts)
        if not isinstance(value, list) or len(value) not in counts:
            self.error("WLD012", f"'{loc[-1]}' must be a list of {wanted} numbers, not {value!r}", loc)
            return None
        return self._checked(value, loc, allowed)

    def number(self, table: dict, loc: tuple, allowed: ranges.Range, default: float) -> float | None:
        value = table.get(loc[-1], default)
        checked = self._checked([value], loc, allowed)
        return checked[0] if checked else None

    def _checked(self, values: list, loc: tuple, allowed: ranges.Range) -> tuple[float, ...] | None:
        if not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values):
            what = f"numbers, not {values!r}" if len(values) > 1 else f"a number, not {values[0]!r}"
            self.error("WLD012", f"'{loc[-1]}' must be {what}", loc)
            return None
        problem = allowed.first_problem(tuple(values))
        if problem:
            self.error("WLD012", f"'{loc[-1]}': {problem}", loc)
            return None
        return tuple(float(v) for v in values)

    def word(self, table: dict, loc: tuple, required: bool = False) -> str | None:
        value = table.get(loc[-1])
        if value is None and required:
            self.error("WLD011", f"[[{loc[0]}]] needs '{loc[-1]}'", loc[:-1], f"add {loc[-1]} = \"...\"")
        elif value is not None and not isinstance(value, str):
            self.error("WLD012", f"'{loc[-1]}' must be a string, not {value!r}", loc)
            return None
        return value

    def name(self, table: dict, loc: tuple, required: bool = False) -> str | None:
        name = self.word(table, loc, required)
        if name is not None and not NAME.fullmatch(name):
            self.error("WLD023", f"'{name}' cannot name an object or container", loc,
                       "use letters, digits and _, starting with a letter or _")
            return None
        return name

    def pose(self, table: dict, loc: tuple) -> tuple[np.ndarray, bool] | None:
        """The 4x4 pose of `position` and `rpy`, and whether z was left out; None (reported)
        when a number is bad or the position is not over the table."""
        position = self.numbers(table, (*loc, "position"), (2, 3), ranges.COORDINATE, required=True)
        rpy = self.numbers(table, (*loc, "rpy"), (3,), RPY) or (0.0, 0.0, 0.0)
        if position is None:
            return None
        low, high = np.subtract(TABLE_CENTRE, TABLE_HALF), np.add(TABLE_CENTRE, TABLE_HALF)
        if not all(low[k] <= position[k] <= high[k] for k in (0, 1)):
            self.error("WLD021", f"({position[0]:g}, {position[1]:g}) is not over the table", (*loc, "position"),
                       f"the table top spans x {low[0]:g} to {high[0]:g} and y {low[1]:g} to {high[1]:g} m")
            return None
        pose = np.eye(4)
        pose[:3, :3] = rotation_rpy(np.radians(rpy))
        pose[:3, 3] = (*position[:2], position[2] if len(position) == 3 else 0.0)
        return pose, len(position) == 2

    def container(self, i: int, table: dict) -> tuple[Container, Location] | None:
        loc = ("container", i)
        name = self.name(table, (*loc, "name"), required=True)
        size = self.numbers(table, (*loc, "size"), (3,), ranges.SIZE, required=True)
        wall = self.number(table, (*loc, "wall"), ranges.SIZE, DEFAULT_WALL)
        placed = self.pose(table, loc)
        if name is None or size is None or wall is None or placed is None:
            return None
        if 2 * wall >= min(size[:2]) or wall >= size[2]:
            self.error("WLD025", f"walls {wall:g} m thick leave no room inside a {' x '.join(f'{s:g}' for s in size)} m box",
                       (*loc, "wall"), "make the walls thinner than half the box's width and than its height")
            return None
        return Container(name, placed[0], size, wall), self.at(loc)

    def placed(self, i: int, table: dict) -> PlacedObject | None:
        loc = ("object", i)
        given = self.name(table, (*loc, "name"))
        pose = self.pose(table, loc)
        if "library" in table and "shape" in table:
            self.error("WLD012", "an object is a library object or a described shape, not both", loc,
                       "keep 'library' or 'shape'")
            return None
        if "library" in table:
            found = self.library_object(table.get("library"), (*loc, "library"))
            if found is None or pose is None:
                return None
            mass = self.number(table, (*loc, "mass"), ranges.WEIGHT, found.mass)
            friction = self.number(table, (*loc, "friction"), ranges.FRICTION, found.friction)
            if "size" in table:
                self.error("WLD012", "a library object has its own size", (*loc, "size"),
                           "leave 'size' out, or describe the object with 'shape'")
                return None
            fixture = self.fixture(table, loc, found)
            if mass is None or friction is None or fixture is None:
                return None
            body = (found.in_fixture() if fixture else found).body(given or found.name, pose[0])
            return PlacedObject(dataclasses.replace(body, mass=mass, friction=friction), pose[1], self.at(loc),
                                given is not None)
        if "fixture" in table:
            self.error("WLD012", "only a bottle or jar with a screw cap stands in a fixture", (*loc, "fixture"),
                       f"leave 'fixture' out; screw-capped objects: {', '.join(_threaded())}")
            return None
        shape = self.word(table, (*loc, "shape"))
        if shape is None:
            if "shape" not in table:
                self.error("WLD011", "[[object]] needs 'library' (an object of the library) or 'shape'", loc,
                           f"library objects: {', '.join(library())}; shapes: box, cylinder, sphere")
            return None
        if shape not in ObjectClass.__members__.values():
            self.error("WLD012", f"no shape '{shape}'", (*loc, "shape"),
                       did_you_mean(shape, [c.value for c in ObjectClass]) or "shapes: box, cylinder, sphere")
            return None
        layout = SIZE_LAYOUT[ObjectClass(shape)]
        size = self.numbers(table, (*loc, "size"), (len(layout),), ranges.SIZE, required=True)
        mass = self.number(table, (*loc, "mass"), ranges.WEIGHT, DEFAULT_WEIGHT)
        friction = self.number(table, (*loc, "friction"), ranges.FRICTION, DEFAULT_FRICTION)
        if size is None or mass is None or friction is None or pose is None:
            return None
        return PlacedObject(Body(given or shape, shape, size, pose[0], mass, friction), pose[1], self.at(loc),
                            given is not None)

    def fixture(self, table: dict, loc: tuple, found: LibraryObject) -> bool | None:
        """Whether a library object stands in a fixture (`fixture = true`); None (reported) when
        the value is not a boolean or the object has no screw cap to hold it for."""
        value = table.get("fixture", False)
        if not isinstance(value, bool):
            self.error("WLD012", f"'fixture' must be true or false, not {value!r}", (*loc, "fixture"),
                       "write fixture = true, or leave it out")
            return None
        if value and found.thread is None:
            self.error("WLD012", f"'{found.name}' has no screw cap: only a bottle or jar with one stands in a fixture",
                       (*loc, "fixture"), f"screw-capped objects: {', '.join(_threaded())}")
            return None
        return value

    def drop(self, i: int, table: dict) -> Drop | None:
        loc = ("drop", i)
        into = self.word(table, (*loc, "into"), required=True)
        names = table.get("objects")
        if names is None:
            self.error("WLD011", "[[drop]] needs 'objects'", loc, "add objects = [\"duck\", ...] from the library")
            return None
        if not isinstance(names, list) or not names:
            self.error("WLD012", f"'objects' must be a list of library objects, not {names!r}", (*loc, "objects"))
            return None
        found = [self.library_object(n, (*loc, "objects")) for n in names]
        clearance = self.number(table, (*loc, "clearance"), ranges.CLEARANCE, 0.0)
        if into is None or None in found or clearance is None:
            return None
        return Drop(tuple((o.name, o) for o in found), into, self.at(loc), clearance)

    def library_object(self, name: object, loc: tuple) -> LibraryObject | None:
        known = library()
        if not isinstance(name, str):
            self.error("WLD012", f"'{loc[-1]}' must name a library object, not {name!r}", loc)
            return None
        if name not in known:
            self.error("WLD020", f"no object '{name}' in the library", loc,
                       did_you_mean(name, known) or f"library objects: {', '.join(known)}")
            return None
        if known[name].unavailable:
            usable = [n for n, o in known.items() if not o.unavailable]
            self.error("WLD026", known[name].unavailable, loc, f"or use one without a mesh: {', '.join(usable)}")
            return None
        return known[name]


def _threaded() -> list[str]:
    """The library's objects with a screw cap."""
    return [name for name, o in library().items() if o.thread is not None]


def _named(placed: list[PlacedObject], drops: list[Drop], containers: tuple[tuple[Container, Location], ...],
           reader: _Reader) -> tuple[list[PlacedObject], list[Drop]]:
    """Every object and container with a name of its own: a given name must be new; a
    nameless object is called after its library object or shape, then _2, _3, ... while
    that is taken."""
    taken: set[str] = set()
    for name, loc in [(c.name, loc) for c, loc in containers] + [(p.body.name, p.loc) for p in placed if p.named]:
        if name in taken:
            reader.found.append(error("WLD023", f"'{name}' names two things", loc,
                                      "give each object and container a name of its own"))
        taken.add(name)

    def fresh(base: str) -> str:
        name, n = base, 1
        while name in taken:
            n += 1
            name = f"{base}_{n}"
        taken.add(name)
        return name

    named = [p if p.named else dataclasses.replace(p, body=dataclasses.replace(p.body, name=fresh(p.body.name)))
             for p in placed]
    return named, [dataclasses.replace(d, objects=tuple((fresh(n), o) for n, o in d.objects)) for d in drops]


def _top(body: Body) -> tuple[np.ndarray, np.ndarray]:
    """(low, high) corners of the world-axis box around a body."""
    half = np.abs(body.pose[:3, :3]) @ (np.array(bounding_box(body.kind, body.size)) / 2)
    return body.pose[:3, 3] - half, body.pose[:3, 3] + half


def _rest(placed: tuple[PlacedObject, ...], fixed: list[Body]) -> list[Body]:
    """The placed bodies, each one that rests put on the highest thing under it: the table,
    an obstacle, a container's floor or wall, an object placed before it."""
    bodies: list[Body] = []
    for p in placed:
        body = p.body
        if p.rests:
            low, high = _top(body)
            tops = [0.0] + [float(h[2]) for other in [*fixed, *bodies] for lo, h in [_top(other)]
                            if (lo[:2] < high[:2]).all() and (h[:2] > low[:2]).all()]
            pose = body.pose.copy()
            pose[2, 3] = max(tops) + (high[2] - low[2]) / 2
            body = dataclasses.replace(body, pose=pose)
        bodies.append(body)
    return bodies


def _overlaps(bodies: list[Body], placed: tuple[PlacedObject, ...], obstacles: tuple[Body, ...]) -> list[Diagnostic]:
    """Placed objects whose bounding boxes cut into an earlier one's, an obstacle or the table."""
    found = []
    for k, (body, p) in enumerate(zip(bodies, placed)):
        low, high = _top(body)
        if low[2] < -OVERLAP:
            found.append(error("WLD022", f"'{body.name}' reaches {-low[2]:.3f} m into the table", p.loc,
                               "raise its z, or leave z out to rest it on the table"))
        for other in [*obstacles, *bodies[:k]]:
            lo, hi = _top(other)
            if (np.minimum(high, hi) - np.maximum(low, lo) > OVERLAP).all():
                found.append(error("WLD022", f"'{body.name}' cuts into '{other.name}'", p.loc,
                                   "move it apart, or leave z out to stack it on top"))
    return found


def _dropped(drop: Drop, box: Container, resting: list[Body], rng: np.random.Generator) -> list[Body]:
    """The drop's objects at random poses over the container's floor: each turned at random
    (uniformly over all rotations), at a random place over the floor that keeps it clear of
    the walls, and as low as keeps it clear of every object already there (bounding spheres)."""
    low, high = box.inner_corners()
    spheres = [(b.pose[:3, 3], float(np.linalg.norm(bounding_box(b.kind, b.size)) / 2)) for b in resting]
    bodies = []
    for name, found in drop.objects:
        radius = float(np.linalg.norm(bounding_box(found.shape.value, found.size)) / 2)
        margin = radius + DROP_GAP
        if (high[:2] - low[:2] < 2 * margin).any():
            raise ValueError(f"'{found.name}' ({2 * radius:.3f} m across, turned any way) does not fit between "
                             f"the walls of '{box.name}'")
        local = np.eye(4)
        local[:3, :3] = _random_rotation(rng)
        local[:2, 3] = rng.uniform(low[:2] + margin, high[:2] - margin)
        local[2, 3] = low[2] + radius + DROP_GAP
        pose = box.pose @ local
        centre = pose[:3, 3]
        for other, r in spheres:
            apart = radius + r + DROP_GAP
            across = float(np.linalg.norm(centre[:2] - other[:2]))
            if across < apart:
                centre[2] = max(centre[2], other[2] + np.sqrt(apart * apart - across * across))
        spheres.append((centre, radius))
        bodies.append(found.body(name, pose))
    return bodies


def _laid(drop: Drop, box: Container, rng: np.random.Generator) -> list[Body]:
    """The drop's objects laid on the container's floor, each resting (`_resting_rotation`) at a
    random turn about the vertical, at a random place whose footprint (in the container's
    axes) keeps `drop.clearance` from the walls and does not overlap the others'. A layout
    where some object finds no place is drawn again from its first object."""
    for _ in range(LAYOUTS):
        laid = _layout(drop, box, rng)
        if laid is not None:
            return laid
    raise ValueError(f"no room to lay {len(drop.objects)} objects {drop.clearance:g} m from the walls of "
                     f"'{box.name}' ({LAYOUTS} layouts drawn)")


def _layout(drop: Drop, box: Container, rng: np.random.Generator) -> list[Body] | None:
    """One layout of `_laid`, or None where an object found no place in `PLACES` draws."""
    low, high = box.inner_corners()
    room = drop.clearance
    footprints: list[tuple[np.ndarray, np.ndarray]] = []  # (low, high) corners in the container's x, y
    bodies = []
    for name, found in drop.objects:
        kind = found.shape.value
        for _ in range(PLACES):
            turn = _resting_rotation(found, rng)
            reach = np.array([half_extent(kind, found.size, turn, axis) for axis in np.eye(3)])
            if (high[:2] - low[:2] - 2 * room < 2 * reach[:2]).any():
                continue
            centre = rng.uniform(low[:2] + room + reach[:2], high[:2] - room - reach[:2])
            if not any((centre + reach[:2] > lo + OVERLAP).all() and (centre - reach[:2] < hi - OVERLAP).all()
                       for lo, hi in footprints):
                break
        else:
            return None
        footprints.append((centre - reach[:2], centre + reach[:2]))
        local = np.eye(4)
        local[:3, :3] = turn
        local[:3, 3] = (*centre, low[2] + reach[2] + LAY_HEIGHT)
        bodies.append(found.body(name, box.pose @ local))
    return bodies


def _resting_rotation(found: LibraryObject, rng: np.random.Generator) -> np.ndarray:
    """A turn that rests the object on the floor, about the vertical at random: a box on one of
    its six faces, a cylinder on an end or on its side, a sphere as it is; an object with a mesh
    (a duck, a mug) as the library stands it, the one face it is sure to rest on."""
    face = np.eye(3)
    if found.mesh is None and found.shape.value == "box":
        down = int(rng.integers(6))
        face = _face_down(down % 3, 1.0 if down < 3 else -1.0)
    elif found.mesh is None and found.shape.value == "cylinder" and rng.integers(2):
        face = _face_down(0, 1.0)  # on its side: its own axis level
    return rotation_rpy((0.0, 0.0, rng.uniform(-np.pi, np.pi))) @ face


def _face_down(axis: int, sign: float) -> np.ndarray:
    """A rotation that turns the body's own `axis` (signed) to point up: the face it points
    away from rests on the floor."""
    up = np.zeros(3)
    up[axis] = sign
    others = [k for k in range(3) if k != axis]
    turn = np.zeros((3, 3))
    turn[2, :] = up
    turn[0, others[0]] = 1.0
    turn[1, :] = np.cross(turn[2, :], turn[0, :])
    return turn


def _random_rotation(rng: np.random.Generator) -> np.ndarray:
    """A rotation drawn uniformly over all rotations: the orthogonal factor of a Gaussian
    matrix, its signs fixed, is uniform over O(3); a reflection, its first axis flipped, is
    a rotation."""
    q, r = np.linalg.qr(rng.standard_normal((3, 3)))
    q = q * np.sign(np.diag(r))
    if np.linalg.det(q) < 0:
        q[:, 0] = -q[:, 0]
    return q


__all__ = ["World", "WorldError", "load_world"]
