"""A robot's links and joints read from its URDF, so nobody retypes a published model.

What a URDF says becomes description `Link`s: the tree (parents before children), joint
origins, axes, limits, damping and friction, masses, centres of mass and inertias, and the
collision and visual geometry; links that are only frames (welded, massless, bare) are
folded into their parents. What a simulator cannot take is refused: a link left out of
the tree, a moving link without a positive mass and a possible inertia, a joint that
cannot move or a shape without size. Reading takes time linear in the links, at most
`MAX_LINKS` of them (`factories/urdf_tree.py`). A mesh (OBJ or STL) is read from where the
URDF names it, checked as every mesh is before an engine sees it, and becomes a mesh shape: both engines collide a
collision mesh's convex hull and draw a visual mesh as it is, without contact or mass. Boxes,
cylinders and spheres are taken as they are. A link whose visual mesh no engine can load (a
COLLADA .dae) is drawn as its collision shapes instead.
What a URDF lacks (servo gains, sensors, the TCP, the hand's DOFs and pads) the robot's
description adds. Anything that cannot be imported is a `UrdfError` naming file:line.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Callable

import numpy as np
from lxml import etree

from atd.model.files import InputError, read_capped
from atd.model.frames import rotation_rpy, rpy_of
from atd.model.meshcheck import SUFFIXES as MESH_SUFFIXES, MeshError, check_mesh
from factories.description import Joint, Link, Origin, Servo, Shape, Vec3
from factories.urdf_physics import Problem, inertia_problem, mass_problem
from factories.urdf_tree import Tree, link_tree

MAX_URDF_BYTES = 16 * 1024 * 1024
_DOCTYPE = re.compile(rb"<!DOCTYPE|<!ENTITY", re.I)
Inertial = tuple[float, Vec3 | None, Vec3 | None, Vec3]
"""A link's mass (kg), centre of mass, moments and products of inertia (None: none given)."""
JOINT_KINDS = {"revolute": "revolute", "continuous": "revolute", "prismatic": "prismatic", "fixed": None}


class UrdfError(ValueError):
    """What cannot be imported, as `FILE:LINE: what; fix`."""


@dataclass(frozen=True)
class UrdfModel:
    """The links of a URDF in tree order (the root first), and where it was read from."""

    path: Path
    """The URDF file."""
    links: tuple[Link, ...]
    """Every link, parents before children, with its joint, mass, inertia and shapes."""
    joint_lines: dict[str, int] = field(default_factory=dict, compare=False)
    """The line of each <joint> in the URDF, by the joint's name: where to point at it."""

    def link(self, name: str) -> Link:
        """The link called `name`; UrdfError naming the URDF when it has none."""
        for link in self.links:
            if link.name == name:
                return link
        raise UrdfError(f"{self.path}: has no link '{name}'; its links: {', '.join(l.name for l in self.links)}")


# What a URDF leaves out of a joint's drive, in proportion to the effort it can give (a
# bigger drive has a bigger rotor and gearbox); chosen so that the Panda's passes
# `atd robots test` (hold within 1 mm, no joint over its speed limit when all run at once).
KP, KV = 150.0, 8.0  # servo gains per N m (or N) of effort
DAMPING = 0.5  # N m s/rad per N m, where the URDF gives no <dynamics damping>
ARMATURE = 0.01  # kg m^2 per N m: the reflected rotor inertia, which a URDF never gives


def default_servo(effort: float) -> Servo:
    """A stiff, well-damped position servo for a joint that can give `effort`: a URDF has no gains."""
    return Servo(kp=KP * effort, kv=KV * effort)


def read_urdf(path: Path, servo: Callable[[float], Servo] = default_servo) -> UrdfModel:
    """The URDF at `path` as description links; `servo(effort)` gives each moving joint its gains."""
    path = Path(path)
    try:
        data = read_capped(path, MAX_URDF_BYTES)
    except InputError as exc:
        raise UrdfError(f"{path}: cannot read the URDF: {exc}") from None
    declaration = _DOCTYPE.search(data)
    if declaration:  # a URDF has no use for one, and an entity can be a bomb: refused before parsing, at its line
        line = data.count(b"\n", 0, declaration.start()) + 1
        raise UrdfError(f"{path}:{line}: the URDF declares a DOCTYPE or "
                        "an entity; remove the declaration (a URDF needs no DTD, and atd expands no entities)")
    parser = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False, huge_tree=False)
    try:
        root = etree.fromstring(data, parser)
    except etree.XMLSyntaxError as exc:
        line = exc.position[0] if exc.position else 1
        raise UrdfError(f"{path}:{line}: not well-formed XML: {exc.msg}; fix the tag at this line") from None
    if root.tag != "robot":
        raise UrdfError(f"{path}:{root.sourceline}: the root element is <{root.tag}>, not <robot>; "
                        "give a URDF file (a xacro must be expanded first: xacro FILE.xacro > FILE.urdf)")
    reader = _Reader(path, servo)
    tree = link_tree(root, reader.fail)
    return UrdfModel(path, reader.links(root, tree), {joint.get("name"): joint.sourceline
                                                     for joint in tree.joints.values()})


@dataclass
class _Reader:
    path: Path
    servo: Callable[[float], Servo]
    colours: dict[str, tuple[float, float, float, float]] = field(default_factory=dict)
    """rgba by material name: a URDF defines a material once and names it in later <visual>s."""

    def fail(self, element: etree._Element, what: str, fix: str) -> UrdfError:
        return UrdfError(f"{self.path}:{element.sourceline}: {what}; {fix}")

    def check(self, element: etree._Element, problem: Problem | None) -> None:
        if problem is not None:
            raise self.fail(element, *problem)

    def positive(self, element: etree._Element, attribute: str, default: float | None = None) -> float:
        """A number above 0: a size, a mass, a limit a drive must reach."""
        value = self.number(element, attribute, default)
        if value <= 0:
            raise self.fail(element, f"{attribute}=\"{element.get(attribute)}\" is not above 0",
                            f"give {attribute} as a number above 0")
        return value

    def non_negative(self, element: etree._Element, attribute: str, default: float) -> float:
        """A number not below 0: damping or friction, which may be absent but never push."""
        value = self.number(element, attribute, default)
        if value < 0:
            raise self.fail(element, f"{attribute}=\"{element.get(attribute)}\" is below 0",
                            f"give {attribute} as 0 or more")
        return value

    def number(self, element: etree._Element, attribute: str, default: float | None = None) -> float:
        text = element.get(attribute)
        if text is None:
            if default is None:
                raise self.fail(element, f"<{element.tag}> has no '{attribute}'", f"add {attribute}=\"...\"")
            return default
        try:
            value = float(text)
        except ValueError:
            raise self.fail(element, f"{attribute}=\"{text}\" is not a number", "write a decimal number") from None
        if not np.isfinite(value):
            raise self.fail(element, f"{attribute}=\"{text}\" is not finite", "write a finite number")
        return value

    def vector(self, element: etree._Element | None, attribute: str, default: Vec3) -> Vec3:
        if element is None or element.get(attribute) is None:
            return default
        parts = element.get(attribute, "").split()
        try:
            values = tuple(float(p) for p in parts)
        except ValueError:
            values = ()
        if len(values) != 3 or not all(np.isfinite(values)):
            raise self.fail(element, f"{attribute}=\"{element.get(attribute)}\" is not three numbers",
                            f"write {attribute}=\"x y z\"")
        return values  # type: ignore[return-value]

    def origin(self, parent: etree._Element) -> Origin:
        element = parent.find("origin")
        return Origin(self.vector(element, "xyz", (0.0, 0.0, 0.0)), self.vector(element, "rpy", (0.0, 0.0, 0.0)))

    def links(self, root: etree._Element, tree: Tree) -> tuple[Link, ...]:
        for material in root.iter("material"):
            colour = material.find("color")
            if colour is not None and material.get("name"):
                self.colours[material.get("name")] = self.rgba(colour)
        return _without_bare_frames([self.link(tree.links[name], tree.joints.get(name)) for name in tree.order])

    def link(self, element: etree._Element, joint_element: etree._Element | None) -> Link:
        mass, com, inertia, products = self.inertial(element, joint_element)
        shapes = tuple(shape for collision in element.findall("collision")
                       for shape in self.geometry(collision, element.get("name")))
        visuals = self.visuals(element)
        joint, origin, parent = None, Origin(), None
        if joint_element is not None:
            parent = joint_element.find("parent").get("link")
            origin = self.origin(joint_element)
            joint = self.joint(joint_element)
        return Link(element.get("name"), parent, origin, mass, shapes, joint, com=com,
                    inertia=inertia, inertia_products=products,  # type: ignore[arg-type]
                    visuals=visuals)

    def inertial(self, link: etree._Element, joint: etree._Element | None) -> Inertial:
        """The link's mass, centre of mass, moments and products of inertia: a link the
        `joint` moves must have them, and a possible body's; a welded one may go without."""
        name = link.get("name")
        moving = joint is not None and JOINT_KINDS.get(joint.get("type")) is not None
        inertial = link.find("inertial")
        if inertial is None:
            if moving:
                raise self.fail(link, f"link '{name}' moves on joint '{joint.get('name')}' but has no <inertial>",
                                "add one with its <mass value=\"...\"/> (kg) and <inertia ixx=... iyy=... izz=.../> "
                                "about its centre of mass (kg m^2)")
            return 0.0, None, None, (0.0, 0.0, 0.0)
        mass_element, tensor = inertial.find("mass"), inertial.find("inertia")
        for element, what, fix in ((mass_element, "mass", "<mass value=\"...\"/> in kg"),
                                   (tensor, "inertia", "<inertia ixx=\"...\" iyy=\"...\" izz=\"...\"/> about its "
                                    "centre of mass (kg m^2)")):
            if element is None and moving:
                raise self.fail(inertial, f"the <inertial> of link '{name}', which a joint moves, has no <{what}>",
                                f"add {fix}")
        mass = self.number(mass_element, "value") if mass_element is not None else 0.0
        self.check(mass_element, mass_problem(name, mass, moving))
        frame = self.origin(inertial)
        if tensor is None:
            return mass, frame.xyz, None, (0.0, 0.0, 0.0)
        moments, products = self.inertia(tensor, frame, name if mass > 0 else None)
        return mass, frame.xyz, moments if mass > 0 else None, products

    def visuals(self, link: etree._Element) -> tuple[Shape, ...]:
        """The link's <visual> shapes in their colours, or none (draw the collision shapes)
        when one is a mesh in a format no engine loads, as a COLLADA .dae."""
        drawn = []
        for visual in link.findall("visual"):
            mesh = visual.find("geometry/mesh")
            if mesh is not None and self.mesh_file(mesh).suffix.lower() not in MESH_SUFFIXES:
                return ()
            drawn += [replace(shape, rgba=self.colour(visual)) for shape in self.geometry(visual, link.get("name"))]
        return tuple(drawn)

    def colour(self, visual: etree._Element) -> tuple[float, float, float, float]:
        """A <visual>'s colour: its material's <color>, else that of the material it names."""
        material = visual.find("material")
        if material is None:
            return Shape.rgba
        colour = material.find("color")
        return self.rgba(colour) if colour is not None else self.colours.get(material.get("name", ""), Shape.rgba)

    def rgba(self, colour: etree._Element) -> tuple[float, float, float, float]:
        values = colour.get("rgba", "").split()
        try:
            rgba = tuple(float(v) for v in values)
        except ValueError:
            rgba = ()
        if len(rgba) != 4 or not all(0 <= v <= 1 for v in rgba):
            raise self.fail(colour, f"rgba=\"{colour.get('rgba')}\" is not four numbers in [0, 1]",
                            "write rgba=\"r g b a\"")
        return rgba  # type: ignore[return-value]

    def inertia(self, tensor: etree._Element, frame: Origin, link: str | None) -> tuple[Vec3, Vec3]:
        """The <inertia>'s moments and products along the link axes: a URDF may give the
        tensor in axes turned by the <inertial>'s rpy. Checked as a body's inertia when it is
        that of `link` (None: a massless frame's, which no simulator sees)."""
        xx, yy, zz, xy, xz, yz = (self.number(tensor, k, 0.0) for k in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz"))
        given = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
        if link is not None:
            self.check(tensor, inertia_problem(link, given))
        turn = rotation_rpy(frame.rpy)
        full = turn @ given @ turn.T
        return ((float(full[0, 0]), float(full[1, 1]), float(full[2, 2])),
                (float(full[0, 1]), float(full[0, 2]), float(full[1, 2])))

    def joint(self, element: etree._Element) -> Joint | None:
        kind = element.get("type")
        if kind not in JOINT_KINDS:
            raise self.fail(element, f"joint '{element.get('name')}' is of type '{kind}', which atd cannot simulate",
                            "use revolute, continuous, prismatic or fixed joints (a floating or planar joint "
                            "has no place in an arm)")
        if JOINT_KINDS[kind] is None:
            return None
        axis = np.asarray(self.vector(element.find("axis"), "xyz", (1.0, 0.0, 0.0)), float)
        if np.linalg.norm(axis) < 1e-9:
            raise self.fail(element.find("axis"), f"joint '{element.get('name')}' has a zero axis",
                            "give its axis xyz as a direction")
        limit = element.find("limit")
        if limit is None:
            raise self.fail(element, f"joint '{element.get('name')}' has no <limit>",
                            "add <limit effort=\"...\" velocity=\"...\" lower=\"...\" upper=\"...\"/>")
        if kind == "continuous":
            lower, upper = -2 * np.pi, 2 * np.pi
        else:
            lower, upper = self.number(limit, "lower", 0.0), self.number(limit, "upper", 0.0)
            if lower >= upper:
                raise self.fail(limit, f"joint '{element.get('name')}' has lower {lower:g} >= upper {upper:g}",
                                "give its range with lower below upper")
        effort, velocity = self.positive(limit, "effort"), self.positive(limit, "velocity")
        dynamics = element.find("dynamics")
        damping = self.non_negative(dynamics, "damping", DAMPING * effort) if dynamics is not None else DAMPING * effort
        friction = self.non_negative(dynamics, "friction", 0.0) if dynamics is not None else 0.0
        unit = tuple(float(v) for v in axis / np.linalg.norm(axis))
        return Joint(element.get("name"), JOINT_KINDS[kind], unit, lower, upper, velocity, effort,  # type: ignore[arg-type]
                     self.servo(effort), damping=damping, friction=friction, armature=ARMATURE * effort)

    def geometry(self, element: etree._Element, link: str) -> tuple[Shape, ...]:
        """A <collision>'s or <visual>'s geometry as a shape in the link frame."""
        origin = self.origin(element)
        geometry = element.find("geometry")
        if geometry is None or len(geometry) == 0:
            raise self.fail(element, f"a <{element.tag}> of link '{link}' has no <geometry>", "add one, or remove it")
        shape = geometry[0]
        if shape.tag == "box":
            size = self.vector(shape, "size", (0.0, 0.0, 0.0))
            if min(size) <= 0:
                raise self.fail(shape, f"a <box> of link '{link}' has size=\"{shape.get('size', '')}\"",
                                "give its three sides, each above 0, in metres: size=\"x y z\"")
            return (Shape("box", tuple(v / 2 for v in size), origin),)
        if shape.tag == "sphere":
            return (Shape("sphere", (self.positive(shape, "radius"),), origin),)
        if shape.tag == "cylinder":
            return (Shape("cylinder", (self.positive(shape, "radius"), self.positive(shape, "length") / 2), origin),)
        if shape.tag == "mesh":
            return (self.mesh(shape, origin),)
        raise self.fail(shape, f"<{shape.tag}> is not a URDF geometry", "use box, cylinder, sphere or mesh")

    def mesh_file(self, mesh: etree._Element) -> Path:
        """The mesh's file: `package://` and relative names are looked for beside the URDF, and
        up its folders (a ROS package's `package://name/...` drops the package's name)."""
        name = mesh.get("filename", "")
        if not name:
            raise self.fail(mesh, "a <mesh> has no filename", "add filename=\"...\"")
        relative = name.removeprefix("package://").removeprefix("file://")
        candidates = [Path(relative)] if Path(relative).is_absolute() else [
            folder / part for folder in (self.path.parent, *self.path.parent.parents)
            for part in (Path(relative), Path(*Path(relative).parts[1:]) if len(Path(relative).parts) > 1 else None)
            if part is not None]
        for candidate in candidates:
            if candidate.is_file():
                return candidate
        raise self.fail(mesh, f"mesh '{name}' is not there (looked for {candidates[0]})",
                        "install the meshes beside the URDF, or correct the filename")

    def mesh(self, mesh: etree._Element, origin: Origin) -> Shape:
        """A mesh as a mesh shape, once its file has passed the check every mesh passes before
        an engine reads it."""
        file = self.mesh_file(mesh)
        scale = self.vector(mesh, "scale", (1.0, 1.0, 1.0))
        try:
            check_mesh(file, scale)
        except MeshError as exc:
            raise self.fail(mesh, f"mesh {file} cannot be simulated: {exc}",
                            "give an OBJ or STL mesh, in metres once scaled") from None
        return Shape("mesh", scale, origin, mesh=file)


def _without_bare_frames(links: list[Link]) -> tuple[Link, ...]:
    """The links less those that are only frames (welded, massless, no geometry: a flange,
    a grasp target), their children hung on their parent with the two origins composed.
    A massless body is no body to a simulator; what a frame draws is drawn by the parent."""
    kept: dict[str, Link] = {}
    frames: dict[str, Link] = {}
    for link in links:
        parent = frames.get(link.parent or "")
        if parent is not None:
            link = replace(link, parent=parent.parent, origin=_composed(parent.origin, link.origin))
        if link.parent is not None and link.joint is None and link.mass <= 0 and not link.shapes:
            frames[link.name] = link
            if link.visuals:
                holder = kept[link.parent]
                kept[holder.name] = replace(holder, visuals=(holder.visuals or holder.shapes) + tuple(
                    replace(shape, origin=_composed(link.origin, shape.origin)) for shape in link.visuals))
        else:
            kept[link.name] = link
    return tuple(kept.values())


def _composed(outer: Origin, inner: Origin) -> Origin:
    """The pose `inner` (in a frame placed by `outer`) in the frame `outer` is given in."""
    pose = outer.matrix() @ inner.matrix()
    return Origin(tuple(float(v) for v in pose[:3, 3]), rpy_of(pose[:3, :3]))  # type: ignore[arg-type]

