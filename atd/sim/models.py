"""One robot description rendered to the two engines' formats (MJCF and URDF) with jinja2.

The templates only print; everything they need (poses as quaternions or rpy, pad
geometry, which links gravity-compensate) is worked out here once, so the two models
cannot drift apart.
"""

from __future__ import annotations

from dataclasses import dataclass, field
import math

import jinja2
import numpy as np

from atd.model.frames import rpy_of as matrix_to_rpy
from atd.sim.scene import COLOURS, TABLE_CENTRE, TABLE_HALF, Body, Scene, bounding_box
from atd.sim.thread import Thread, jaws
from factories.description import FingerPad, Link, Origin, RobotDescription, Shape
from factories.parts import PAD

#: A depth camera's optical frame (z along the view, y down the image) turned into a MuJoCo
#: camera's (looking along -z, y up the image): half a turn about x.
_MUJOCO_VIEW = np.diag([1.0, -1.0, -1.0, 1.0])
#: Contacts reported per finger pad each physics step, strongest first: a box face on a pad
#: makes four, an edge two; the weakest beyond these carry almost nothing.
PAD_CONTACTS = 8
#: s: MuJoCo's default contact time constant (solref), which every geom but a cap keeps.
CONTACT_TIMECONST = 0.02


def matrix_to_quat(r: np.ndarray) -> tuple[float, float, float, float]:
    """(w, x, y, z) of a rotation matrix. On Python floats: a recording converts three poses
    per sample, and numpy's scalar functions cost several times what `math` does."""
    (a, b, c), (d, e, f), (g, h, i) = r.tolist()
    w = math.sqrt(max(0.0, 1.0 + a + e + i)) / 2
    x = math.copysign(math.sqrt(max(0.0, 1.0 + a - e - i)) / 2, h - f)
    y = math.copysign(math.sqrt(max(0.0, 1.0 - a + e - i)) / 2, c - g)
    z = math.copysign(math.sqrt(max(0.0, 1.0 - a - e + i)) / 2, d - b)
    return (w, x, y, z)


def _fmt(values) -> str:
    return " ".join(f"{float(v):.6g}" for v in values)


@dataclass
class Placed:
    """A pose ready for either format."""

    pos: str
    quat: str
    rpy: str

    @classmethod
    def of(cls, m: np.ndarray) -> Placed:
        return cls(_fmt(m[:3, 3]), _fmt(matrix_to_quat(m[:3, :3])), _fmt(matrix_to_rpy(m[:3, :3])))


@dataclass
class GeomView:
    name: str
    kind: str
    mjcf_size: str
    urdf_size: dict[str, str]
    at: Placed
    rgba: str
    shape: Shape


@dataclass
class BodyView:
    link: Link
    at: Placed
    geoms: list[GeomView]
    """What collides."""
    visuals: list[GeomView]
    """What is drawn: the link's visual shapes, else its collision geoms themselves."""
    sites: list[tuple[str, Placed]]
    pads: list[tuple[FingerPad, GeomView]]
    gravcomp: bool
    children: list[BodyView] = field(default_factory=list)


def _geom(name: str, shape: Shape, frame: np.ndarray | None = None) -> GeomView:
    m = shape.origin.matrix() if frame is None else frame
    s = shape.size
    if shape.kind == "mesh":  # both engines collide a moving body's mesh as its convex hull
        urdf = {"filename": str(shape.mesh), "scale": _fmt(s)}
    elif shape.kind == "box":
        urdf = {"size": _fmt(2 * v for v in s)}
    elif shape.kind == "sphere":
        urdf = {"radius": _fmt(s)}
    else:  # URDF lengths are whole (PyBullet's capsule length excludes the caps, as MJCF's does)
        urdf = {"radius": _fmt(s[:1]), "length": _fmt([2 * s[1]])}
    return GeomView(name, shape.kind, _fmt(s), urdf, Placed.of(m), _fmt(shape.rgba), shape)


def _pad_frame(pad: FingerPad) -> np.ndarray:
    """Centre of the pad's box in its link: half a thickness behind the sensing surface."""
    shift = np.eye(4)
    shift[2, 3] = -pad.thickness / 2
    return pad.origin.matrix() @ shift


def _pad_geom(pad: FingerPad) -> GeomView:
    shape = Shape("box", (pad.half_size[0], pad.half_size[1], pad.thickness / 2), rgba=PAD)
    return _geom(pad.name, shape, _pad_frame(pad))


def body_tree(d: RobotDescription) -> BodyView:
    """The description's links as a tree, with sites and pads hung on their links."""
    arm_moved: set[str] = set()  # links the arm carries, hand excluded: gravity-compensated like a real arm's servo
    for link in d.links:
        moved = (link.joint is not None and link.joint.name in d.arm_joints) or link.parent in arm_moved
        if moved and link.name not in d.hand_links:
            arm_moved.add(link.name)
    views: dict[str, BodyView] = {}
    root = None
    for link in d.links:
        geoms = [_geom(f"{link.name}_{i}", s) for i, s in enumerate(link.shapes)]
        view = BodyView(
            link=link,
            at=Placed.of((d.base if link.parent is None else link.origin).matrix()),
            geoms=geoms,
            visuals=[_geom(f"{link.name}_visual_{i}", s) for i, s in enumerate(link.visuals)] or geoms,
            sites=[(s.name, Placed.of(s.origin.matrix())) for s in d.sites if s.link == link.name],
            pads=[(p, _pad_geom(p)) for p in d.hand.pads if p.link == link.name],
            gravcomp=link.name in arm_moved,
        )
        views[link.name] = view
        if link.parent is None:
            root = view
        else:
            views[link.parent].children.append(view)
    assert root is not None
    return root


def _depth_first(view: BodyView):
    """Bodies in MJCF order, which is also the order of their joints in qpos."""
    yield view
    for child in view.children:
        yield from _depth_first(child)


_ENV = jinja2.Environment(
    loader=jinja2.PackageLoader("atd.sim", "templates"),
    undefined=jinja2.StrictUndefined,
    trim_blocks=True,
    lstrip_blocks=True,
    keep_trailing_newline=True,
)


def compile_templates() -> None:
    """Compile every model template now (jinja2 keeps them): a process that forks workers does
    it once for all of them, where each would otherwise do it on its first trial."""
    for name in _ENV.list_templates():
        _ENV.get_template(name)


@dataclass
class MeshView:
    """One mesh geom of a body and the asset it draws on."""

    geom: str
    asset: str
    file: str
    scale: str
    at: Placed


def _meshes(body: Body, name: str) -> list[MeshView]:
    """The body's collision meshes, named `name`, `name_1`, ..."""
    frame = Placed.of(body.mesh_frame if body.mesh_frame is not None else np.eye(4))
    return [MeshView(name + (f"_{i}" if i else ""), f"{name}_mesh" + (f"_{i}" if i else ""), str(path),
                     _fmt(body.mesh_scale), frame)
            for i, path in enumerate(body.collision_meshes)]


def _body(body: Body, name: str | None = None) -> dict:
    """A body ready for the template; `name` names its MJCF elements (default: the body's)."""
    name = name or body.name
    return {"body": body, "name": name, "at": Placed.of(body.pose), "size": _fmt(body.half_extents),
            "inertia": _fmt(body.inertia()), "meshes": _meshes(body, name), "thread": _thread(body)}


def cap_timeconst(thread: Thread, body_mass: float) -> float:
    """The time constant (s) of a threaded body's cap's contacts. MuJoCo lets a contact give way
    in proportion to its body's inverse mass: on CONTACT_TIMECONST a cap of a few grams let the
    pads sink millimetres into it (docs/unscrew-campaign.md). Scaled by the root of the cap's
    mass over the body's, a cap gives way as little as the bottle under it (MuJoCo keeps at
    least two steps)."""
    return CONTACT_TIMECONST * math.sqrt(thread.cap_mass / body_mass)


def _thread(body: Body) -> dict | None:
    """A threaded body's parts for the template (atd/sim/thread.py): main part and neck as
    (centre, MJCF size), where its nut starts and where its cap stands, in the world."""
    t = body.thread
    if t is None:
        return None
    height = body.size[-1]
    main_z, neck_z, cap_z = t.parts(height)
    main = (*body.half_extents[:-1], t.main_height(height) / 2)
    return {"t": t, "main": (_fmt((0, 0, main_z)), _fmt(main)), "neck": (_fmt((0, 0, neck_z)), _fmt((t.neck_radius, t.neck_height / 2))),
            "nut": _fmt((0, 0, cap_z)), "cap": Placed.of(t.closed_cap(body.pose, height)), "cap_size": _fmt((t.cap_radius, t.cap_height / 2)),
            "cap_inertia": _fmt(t.cap_inertia()), "cap_solref": _fmt((cap_timeconst(t, body.own_mass), 1)), "coupling": _fmt((0, t.pitch / (2 * math.pi), 0, 0, 0)),
            "jaws": [{"at": Placed.of(pose), "size": _fmt(s / 2 for s in size)}
                     for pose, size in (jaws(body.pose, bounding_box(body.kind, body.size)[:2], height) if t.fixture else [])]}


def object_name(body: Body) -> str:
    """A free object's MJCF name: apart from the robot's links, the table and the obstacles,
    whatever the world file calls it."""
    return f"object:{body.name}"


def thread_names(body: Body) -> dict[str, str]:
    """The MJCF names of a threaded object's cap body, nut joints, thread weld and fixture weld."""
    return {part: f"{part}:{body.name}" for part in ("cap", "lift", "turn", "thread", "fixture")}


def _visual_meshes(root: BodyView) -> list[GeomView]:
    return [g for b in _depth_first(root) if b.visuals is not b.geoms for g in b.visuals if g.kind == "mesh"]


def visual_meshes(d: RobotDescription) -> dict[str, Shape]:
    """The mesh assets of `mjcf(d, ...)` that are only drawn, by name. MuJoCo's OBJ reader
    keeps only a file's first object, and a visual OBJ is often several (pybullet_data's
    Panda hand: five), so the MuJoCo engine gives it these meshes' triangles itself."""
    return {g.name: g.shape for g in _visual_meshes(body_tree(d))}


def mjcf(d: RobotDescription, scene: Scene) -> str:
    """The whole MuJoCo world: options, defaults, table, obstacles, containers, objects, robot,
    cameras, sensors, home key."""
    hand_home = d.hand_joint_targets(np.array([dof.open for dof in d.hand.dofs]))
    hand_joints = [name for name in d.joints if name not in d.arm_joints]
    home = dict(zip(d.arm_joints, d.home)) | hand_home
    root = body_tree(d)
    qpos = [home.get(b.link.joint.name, 0.0) for b in _depth_first(root) if b.link.joint]
    for o in scene.objects:  # in the order of the MJCF: the object, its nut's lift and turn, its cap
        qpos += list(o.pose[:3, 3]) + list(matrix_to_quat(o.pose[:3, :3]))
        if o.thread is not None:
            cap = o.thread.closed_cap(o.pose, o.size[-1])
            qpos += [0.0, 0.0] + list(cap[:3, 3]) + list(matrix_to_quat(cap[:3, :3]))
    cameras = [{"camera": c, "at": Placed.of(c.origin.matrix() @ _MUJOCO_VIEW)} for c in d.cameras]
    return _ENV.get_template("scene.mjcf.j2").render(
        d=d,
        root=root,
        table={"pos": _fmt(TABLE_CENTRE), "size": _fmt(TABLE_HALF)} if scene.table else None,
        objects=[_body(o, object_name(o)) for o in scene.objects],
        obstacles=[_body(b) for b in scene.obstacles],
        container_parts=[_body(b, f"container:{b.name}") for c in scene.containers for b in c.parts()],
        cameras=cameras,
        offscreen=(max([640] + [c.width for c in d.cameras]), max([480] + [c.height for c in d.cameras])),
        hand_joints=hand_joints,
        key_qpos=_fmt(qpos),
        key_ctrl=_fmt([home.get(name, 0.0) for name in list(d.arm_joints) + hand_joints]),
        robot_meshes=[g for b in _depth_first(root) for g in b.geoms if g.kind == "mesh"] + _visual_meshes(root),
        pad_contacts=PAD_CONTACTS,
        colours={kind: _fmt(rgba) for kind, rgba in COLOURS.items()},
        fmt=_fmt,
    )


def urdf(d: RobotDescription) -> str:
    """The robot alone (PyBullet places it at `d.base` and builds the scene itself).

    Pads become links of their own, welded to their finger, so that PyBullet's
    contact reports (which name links, not shapes) tell pad contacts apart.
    """
    return _ENV.get_template("robot.urdf.j2").render(d=d, root=body_tree(d), origin=Placed.of(Origin().matrix()), fmt=_fmt)
