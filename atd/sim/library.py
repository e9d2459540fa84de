"""The object library: everyday objects (thesis 3.4.1 grasped ten, 3.4.3 emptied a box of
five) for campaigns and world files: what the robot believes of each, and what the
simulator makes of it.

The belief is a primitive (class, size, weight, friction) the factories plan the grasp
with. The truth is that primitive or, where `pybullet_data` ships one, a real mesh
scaled so that its bounding box is the believed shape. Sizes fit every hand's top-down
pinch: the jaws of the Melfa and Baxter close along world y, up to 68 mm apart, and
Baxter's no closer than 26 mm, so the width along y stays within 35-57 mm; and no
object is under 45 mm tall (nothing under 40 mm was lifted by every hand, measured).

Masses come from a material density times the volume where the object is solid (cited
inline); friction is the pad-on-object coefficient, which both engines apply (MuJoCo by
geom priority, Bullet by multiplying with the pad's 1).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from functools import cache
from pathlib import Path

import numpy as np

from atd.model import ObjectClass, ObjectInfo, Pose
from atd.model.meshcheck import mesh_points
from atd.sim.convex import convex_parts
from atd.sim import optional
from atd.sim.scene import Body, bounding_box
from atd.sim.thread import Thread

# Quarter turns that stand a mesh file up in the world frame (table z = 0, z up).
_AS_IS = np.eye(3)
_Y_UP = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])  # file's y becomes z
_Y_TO_X = np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # file's y becomes x


class UnknownObject(LookupError):
    """No library object has that name; the message lists the ones there are."""


class MeshUnavailable(LookupError):
    """The object's mesh ships with PyBullet (`pybullet_data`), which is not installed."""


@dataclass(frozen=True)
class LibraryObject:
    """One everyday object. `size` follows `atd.model.vocabulary.SIZE_LAYOUT` for `shape`;
    `mesh` is a file inside the installed `pybullet_data`, stood up by `turn` (a signed
    permutation); `concave` meshes collide as their convex parts. A `thread` makes it a
    bottle or jar with a screw cap (atd/sim/thread.py): `size` is then the whole object's,
    cap included, and `mass` includes the cap's."""

    name: str
    description: str
    shape: ObjectClass
    size: tuple[float, ...]
    mass: float  # kg
    friction: float
    source: str  # where the figures come from
    mesh: str | None = None
    turn: np.ndarray = dataclasses.field(default_factory=lambda: _AS_IS, compare=False, repr=False)
    concave: bool = False
    thread: Thread | None = None

    def in_fixture(self) -> LibraryObject:
        """This bottle or jar held upright in a clamp on the table (for one-arm robots);
        ValueError for an object without a screw cap."""
        if self.thread is None:
            raise ValueError(f"'{self.name}' has no screw cap: only a bottle or jar with one stands in a fixture")
        return dataclasses.replace(self, thread=dataclasses.replace(self.thread, fixture=True))

    def object_info(self, x: float, y: float, yaw: float = 0.0) -> ObjectInfo:
        """What the robot believes: the object resting on the table at (x, y), turned by
        `yaw` (rad) about the vertical."""
        info = ObjectInfo(weight=self.mass, friction=self.friction, object_class=self.shape, size=self.size)
        c, s = math.cos(yaw), math.sin(yaw)
        pose = Pose(matrix=(c, 0.0 - s, 0.0, x, s, c, 0.0, y, 0.0, 0.0, 1.0, info.half_height, 0.0, 0.0, 0.0, 1.0))
        return info.model_copy(update={"pose": pose})

    @property
    def unavailable(self) -> str | None:
        """Why this object cannot be built here (its mesh needs PyBullet), or None."""
        if self.mesh is None or optional.pybullet_installed():
            return None
        return optional.pybullet_missing(f"library object '{self.name}' (a mesh from pybullet_data)")

    def body(self, name: str, pose: np.ndarray) -> Body:
        """The simulator's truth for this object at `pose` (its geometric centre), named `name`."""
        return self.realize(Body(name, self.shape.value, self.size, pose, self.mass, self.friction))

    def realize(self, body: Body) -> Body:
        """The simulator's truth for a belief `body`: same name, pose, mass and friction;
        the mesh, scaled per axis and centred so that the bounding box of what collides
        (the mesh's hull, or its convex parts, which V-HACD makes up to 2% larger) is the
        body's. A threaded object gets its thread."""
        if self.thread is not None:
            return dataclasses.replace(body, thread=self.thread)
        if self.mesh is None:
            return body
        source = mesh_file(self.mesh)
        parts = convex_parts(source) if self.concave else ()
        box = np.array(bounding_box(body.kind, body.size))
        stood = np.vstack([mesh_points(f) for f in parts or (source,)]) @ self.turn.T
        low, high = stood.min(axis=0), stood.max(axis=0)
        world_scale = box / (high - low)
        frame = np.eye(4)
        frame[:3, :3] = self.turn
        frame[:3, 3] = -world_scale * (low + high) / 2
        scale = np.abs(self.turn).T @ world_scale  # in the file's own axes
        return dataclasses.replace(
            body, kind="mesh", size=tuple(float(v) for v in box), mesh=source,
            mesh_scale=tuple(float(v) for v in scale), mesh_frame=frame,
            mesh_parts=parts,
        )


def mesh_file(relative: str) -> Path:
    """A mesh of the installed `pybullet_data` package, used where it is, never copied."""
    if not optional.pybullet_installed():
        raise MeshUnavailable(optional.pybullet_missing(f"the mesh '{relative}' from pybullet_data"))
    import pybullet_data

    path = Path(pybullet_data.getDataPath()) / relative
    if not path.is_file():
        raise FileNotFoundError(f"{path}: pybullet_data has no '{relative}'; reinstall it with "
                                "`pip install --force-reinstall pybullet`")
    return path


def library() -> dict[str, LibraryObject]:
    """Every object, by name (a fresh dict: the caller may narrow it): the everyday objects,
    then the bottles and jars with screw caps."""
    return {o.name: o for o in (*_objects(), *_screw_capped())}


@cache
def _objects() -> tuple[LibraryObject, ...]:
    cyl, box, ball = ObjectClass.CYLINDER, ObjectClass.BOX, ObjectClass.SPHERE
    return (
        LibraryObject("cylinder", "plastic cylinder of examples/grasp_and_lift.xml, 40 mm across, 80 mm tall",
                      cyl, (0.02, 0.08), 0.15, 0.8, "examples/grasp_and_lift.xml (thesis Fig. 7.2)"),
        # A sphere, not the soccer-ball mesh: that mesh's faceted hull rolled 14 mm off its
        # place on the table in PyBullet within 0.5 s (measured).
        LibraryObject("ball", "solid rubber toy ball, 50 mm", ball, (0.025,), 0.07, 0.9,
                      "mass: 65 cm^3 of rubber at 1.1 g/cm^3; friction: rubber on rubber pads, assumed"),
        # 48 mm wide, not a 19 mm roll lying flat: the fingers could not close on anything
        # under 40 mm tall (a 30 mm box: no lift on any hand but the Barrett, measured).
        LibraryObject("tape", "roll of 48 mm packing tape, nearly used up, 57 mm across, lying flat", cyl,
                      (0.0285, 0.048), 0.06, 0.7,
                      "torus mesh stretched to the roll's width; mass of a nearly used-up roll, assumed",
                      mesh="torus/torus_textured.obj", turn=_Y_UP, concave=True),
        LibraryObject("wood", "beech building block 70 x 40 x 45 mm", box, (0.07, 0.04, 0.045), 0.09, 0.6,
                      "mass: 126 cm^3 of beech at 0.72 g/cm^3; Jenga block mesh (a box)",
                      mesh="jenga/jenga.obj"),
        LibraryObject("mug", "porcelain espresso cup, 49 mm across, handle pointing away from the robot", box,
                      (0.073, 0.049, 0.06), 0.09, 0.6,
                      "pybullet_data mug at 0.6 scale; mass of a porcelain demitasse cup, assumed",
                      mesh="objects/mug.obj", turn=_Y_TO_X, concave=True),
        LibraryObject("duck", "vinyl rubber duck, 75 mm beak to tail", box, (0.0745, 0.052, 0.069), 0.03, 0.9,
                      "pybullet_data duck at 0.045 scale; mass of a hollow vinyl toy, assumed",
                      mesh="duck.obj", turn=_Y_UP, concave=True),
        LibraryObject("bunny", "hollow ceramic bunny figurine (the Stanford bunny), 79 mm long", box,
                      (0.079, 0.037, 0.058), 0.12, 0.6,
                      "Stanford bunny mesh at 0.04 scale; mass of a hollow ceramic figurine, assumed",
                      mesh="bunny.obj", turn=_Y_TO_X @ _Y_UP, concave=True),
        LibraryObject("spray", "travel-size aluminium spray can, 38 mm across, 85 mm tall", cyl, (0.019, 0.085),
                      0.07, 0.5, "50 ml travel can: about 40 g of contents and 30 g of can, assumed"),
        LibraryObject("stapler", "mini stapler, 80 x 40 x 50 mm", box, (0.08, 0.04, 0.05), 0.12, 0.6,
                      "typical pocket stapler figures, assumed"),
        LibraryObject("speaker", "pocket Bluetooth speaker, 65 x 50 x 50 mm", box, (0.065, 0.05, 0.05), 0.15, 0.7,
                      "typical pocket speaker figures, assumed; rubberised housing"),
        LibraryObject("weight", "steel weight, 35 mm across, 45 mm tall", cyl, (0.0175, 0.045), 0.34, 0.5,
                      "mass: 43.3 cm^3 of steel at 7.85 g/cm^3; friction of smooth steel, assumed"),
    )


#: Rise per turn of the SPI/GPI continuous-thread finishes from 28 to 66 mm: 6 threads per inch.
SIX_TPI = 0.0254 / 6


@cache
def _screw_capped() -> tuple[LibraryObject, ...]:
    """Eight bottles and jars with screw caps (thesis 3.4.2, Fig. 3.17: different shapes,
    weights, caps and threads). Size: the whole object, cap included; mass: contents,
    container and cap. A finish `D-400` has one turn of thread, `-410` one and a half,
    `-415` two (SPI/GPI finish series); a lug (twist-off) cap a quarter turn. A cap's outer
    diameter is the finish's plus 2-4 mm; thread torques are those of a cap closed by hand
    after a first opening (assumed), a fraction of a factory closure's."""
    cyl, box = ObjectClass.CYLINDER, ObjectClass.BOX

    def screw(name: str, description: str, shape: ObjectClass, size: tuple[float, ...], mass: float, friction: float,
              source: str, neck: tuple[float, float], cap: tuple[float, float, float], pitch: float, turns: float,
              torque: float) -> LibraryObject:
        thread = Thread(neck[0], neck[1], cap[0], cap[1], cap[2], pitch, turns, torque)
        return LibraryObject(name, description, shape, size, mass, friction, source, thread=thread)

    return (
        screw("water_bottle", "half-full 0.5 l PET water bottle, 64 mm across, 205 mm tall, 28 mm cap", cyl,
              (0.032, 0.205), 0.27, 0.7, "250 ml of water and a 20 g bottle; 28-410 finish (6 TPI, 1.5 turns)",
              (0.0125, 0.012), (0.015, 0.017, 0.0025), SIX_TPI, 1.5, 0.04),
        screw("juice_bottle", "0.25 l glass juice bottle, 60 mm across, 170 mm tall, 38 mm metal cap", cyl,
              (0.030, 0.17), 0.36, 0.6, "200 g of glass and 150 ml of juice; 38-400 finish (6 TPI, 1 turn)",
              (0.018, 0.012), (0.020, 0.014, 0.005), SIX_TPI, 1.0, 0.06),
        screw("shampoo_bottle", "flat 250 ml shampoo bottle, 65 x 45 mm, 190 mm tall, 28 mm flip-top cap", box,
              (0.065, 0.045, 0.19), 0.30, 0.5, "about 250 g of shampoo in a 30 g bottle; 28-415 finish (6 TPI, 2 turns)",
              (0.0125, 0.010), (0.015, 0.020, 0.004), SIX_TPI, 2.0, 0.04),
        screw("vitamin_jar", "wide-mouth plastic pill jar, 60 mm across, 100 mm tall, 45 mm cap", cyl,
              (0.030, 0.10), 0.08, 0.6, "60 tablets and a 25 g jar; 45-400 finish (6 TPI, 1 turn)",
              (0.022, 0.010), (0.024, 0.016, 0.006), SIX_TPI, 1.0, 0.06),
        screw("jam_jar", "glass jam jar, 66 mm across, 105 mm tall, 58 mm twist-off lug cap", cyl,
              (0.033, 0.105), 0.35, 0.6,
              "150 g of glass, 200 g of jam; lug finish: a quarter turn, rising about 2.5 mm (assumed)",
              (0.028, 0.008), (0.030, 0.012, 0.012), 0.010, 0.25, 0.12),
        screw("coffee_jar", "square plastic instant-coffee jar, 60 x 60 mm, 130 mm tall, 53 mm cap", box,
              (0.06, 0.06, 0.13), 0.25, 0.6, "200 g of coffee, a 40 g jar; 53-400 finish (6 TPI, 1 turn)",
              (0.025, 0.010), (0.0275, 0.015, 0.010), SIX_TPI, 1.0, 0.10),
        screw("spice_jar", "glass spice jar, 45 mm across, 100 mm tall, cap as wide as the jar", cyl,
              (0.0225, 0.10), 0.12, 0.6, "80 g of glass, 40 g of spice; 43-400 finish (6 TPI, 1 turn)",
              (0.0205, 0.008), (0.0225, 0.014, 0.004), SIX_TPI, 1.0, 0.05),
        screw("syrup_bottle", "amber glass syrup bottle, 54 mm across, 130 mm tall, 28 mm cap with a fine thread", cyl,
              (0.027, 0.13), 0.25, 0.6,
              "120 g of glass, 100 ml of syrup; a pharmacy cap with a 3 mm pitch, 2.5 turns (assumed)",
              (0.0125, 0.014), (0.015, 0.016, 0.003), 0.003, 2.5, 0.04),
    )


def get(name: str) -> LibraryObject:
    """The library object called `name`."""
    objects = library()
    if name not in objects:
        raise UnknownObject(f"no object '{name}' in the library; choose one of: {', '.join(objects)}")
    return objects[name]
