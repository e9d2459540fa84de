"""Scripted worlds for the perception tests: an open box within the Melfa's reach, in view of
the Kinect and clear of the parked hand, with cubes put where a test needs them. The tests
may read the truth (where the cubes rest); the controllers never do."""

from __future__ import annotations

import numpy as np

from atd.sim import load_description, make_robot
from atd.sim.scene import DEFAULT_FRICTION, Body, Container, Scene
from atd.sim.simrobot import SimRobot
from atd.model.estd import Controller
from primitives.perception.container import ContainerBelief

WALL = 0.01
BOX_POSE = np.eye(4)
BOX_POSE[:3, 3] = (0.18, 0.15, 0.0)
BOX = Container("box", BOX_POSE, (0.24, 0.20, 0.08), WALL)  # inside: x 0.07-0.29, y 0.06-0.24, floor at z 0.01
BELIEF = ContainerBelief.of(BOX_POSE, np.array(BOX.size), WALL)
FLOOR = WALL
CORNER = (0.26, 0.21)  # a 5 cm cube here stands 0.5 cm from the far walls of the box
MELFA_REACH = load_description("melfa").hand_reach("open")  # m the Melfa's fingertips reach below its TCP


def cube(name: str, xy: tuple[float, float], size: float | tuple[float, float] = 0.05,
         height: float | None = None) -> Body:
    """A box standing on the box's floor at `xy`: a cube of `size`, or `height` tall; `size`
    (x, y) for a bar."""
    x, y = (size, size) if isinstance(size, float) else size
    tall = x if height is None else height
    pose = np.eye(4)
    pose[:3, 3] = (*xy, FLOOR + tall / 2)
    return Body(name, "box", (x, y, tall), pose, 0.2, DEFAULT_FRICTION)


def box_world(*objects: Body, engine: str = "mujoco") -> SimRobot:
    """The Melfa at home beside the box holding `objects`, settled."""
    return make_robot(load_description("melfa"), Scene(objects=objects, containers=(BOX,), settle=bool(objects)),
                      engine)


def container_params() -> dict:
    """The box as a perceive state's parameters give it: what the task believes."""
    return {"container_pose": tuple(BOX_POSE.reshape(-1)), "container_size": BOX.size, "container_wall": WALL}


def perceive(method: str, **params) -> Controller:
    """A perceive arm controller for the Melfa looking in the box, writing under 'found'."""
    return Controller(name="perceive", params={"method": method, "writes": "found", "hand_reach": MELFA_REACH,
                                               "grasp_reach": MELFA_REACH,
                                               **container_params(), **params})
