"""Simulated robots: one robot description, rendered for MuJoCo or PyBullet, behind the
robot interface of `primitives.robot`."""

from __future__ import annotations

import importlib
import importlib.util
import os
import pkgutil

# Headless pictures (videos of runs): MuJoCo picks its OpenGL backend when first imported.
os.environ.setdefault("MUJOCO_GL", "egl")

import factories
from atd.sim.scene import Scene, box_scene
from atd.sim.simrobot import SimRobot
from factories.description import RobotDescription

ENGINES = ("mujoco", "pybullet")


class UnknownRobot(LookupError):
    """No description for that robot name or arm; the message lists what exists."""


def known_robots() -> list[str]:
    """Robots that ship a description module under `factories/`."""
    return sorted(
        info.name
        for info in pkgutil.iter_modules(factories.__path__)
        if info.ispkg and importlib.util.find_spec(f"factories.{info.name}.description") is not None
    )


def variants() -> list[tuple[str, str | None]]:
    """Every (robot, arm) model there is."""
    return [(robot, arm) for robot in known_robots() for arm in importlib.import_module(f"factories.{robot}.description").ARMS]


def load_description(robot: str, arm: str | None = None) -> RobotDescription:
    """The robot's description from `factories.<robot>.description` (until the factory
    registry can be asked)."""
    if robot not in known_robots():
        raise UnknownRobot(f"no robot named '{robot}'; known robots: {', '.join(known_robots())}")
    module = importlib.import_module(f"factories.{robot}.description")
    try:
        return module.description(arm)
    except ValueError as exc:
        raise UnknownRobot(str(exc)) from None


def make_robot(description: RobotDescription, scene: Scene | None = None, engine: str = "mujoco", seed: int = 0) -> SimRobot:
    """A simulated robot in `scene` (default: a 5 cm box in the work area) on the named engine."""
    scene = scene if scene is not None else box_scene()
    if engine == "mujoco":
        from atd.sim.mujoco_engine import MujocoRobot

        return MujocoRobot(description, scene, seed)
    if engine == "pybullet":
        from atd.sim.pybullet_engine import PybulletRobot

        return PybulletRobot(description, scene, seed)
    raise ValueError(f"unknown engine '{engine}'; use one of {', '.join(ENGINES)}")
