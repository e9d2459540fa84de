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
from dataclasses import dataclass
from functools import cache
from pathlib import Path

import numpy as np
import pybullet_data

from atd.model import ObjectClass, ObjectInfo, Pose
from atd.model.meshcheck import mesh_points
from atd.sim.convex import convex_parts
from atd.sim.scene import Body, bounding_box

# Quarter turns that stand a mesh file up in the world frame (table z = 0, z up).
_AS_IS = np.eye(3)
_Y_UP = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])  # file's y becomes z
_Y_TO_X = np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # file's y becomes x


class UnknownObject(LookupError):
    """No library object has that name; the message lists the ones there are."""


@dataclass(frozen=True)
class LibraryObject:
    """One everyday object. `size` follows `atd.model.vocabulary.SIZE_LAYOUT` for `shape`;
    `mesh` is a file inside the installed `pybullet_data`, stood up by `turn` (a signed
    permutation); `concave` meshes collide as their convex parts."""

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

    def object_info(self, x: float, y: float) -> ObjectInfo:
        """What the robot believes: the object resting on the table at (x, y)."""
        info = ObjectInfo(weight=self.mass, friction=self.friction, object_class=self.shape, size=self.size)
        return info.model_copy(update={"pose": Pose.from_position((x, y, info.half_height))})

    def body(self, name: str, pose: np.ndarray) -> Body:
        """The simulator's truth for this object at `pose` (its geometric centre), named `name`."""
        return self.realize(Body(name, self.shape.value, self.size, pose, self.mass, self.friction))

    def realize(self, body: Body) -> Body:
        """The simulator's truth for a belief `body`: same name, pose, mass and friction;
        the mesh, scaled per axis and centred so that the bounding box of what collides
        (the mesh's hull, or its convex parts, which V-HACD makes up to 2% larger) is the
        body's."""
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
    path = Path(pybullet_data.getDataPath()) / relative
    if not path.is_file():
        raise FileNotFoundError(f"{path}: pybullet_data has no '{relative}'; reinstall it with "
                                "`pip install --force-reinstall pybullet`")
    return path


def library() -> dict[str, LibraryObject]:
    """Every object, by name (a fresh dict: the caller may narrow it)."""
    return {o.name: o for o in _objects()}


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


def get(name: str) -> LibraryObject:
    """The library object called `name`."""
    objects = library()
    if name not in objects:
        raise UnknownObject(f"no object '{name}' in the library; choose one of: {', '.join(objects)}")
    return objects[name]
