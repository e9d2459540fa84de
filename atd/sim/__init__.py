"""Simulated robots: one robot description, rendered for MuJoCo or PyBullet, behind the
robot interface of `primitives.robot`."""

from __future__ import annotations

import os

# Headless pictures (videos of runs): MuJoCo picks its OpenGL backend when first imported.
os.environ.setdefault("MUJOCO_GL", "egl")

from atd.sim.scene import Scene, box_scene
from atd.sim.simrobot import SimRobot
from factories.description import RobotDescription
from factories.registry import UnknownRobot, create, installed

__all__ = ["ENGINES", "UnknownRobot", "installed_engines", "load_description", "make_arms", "make_robot", "variants"]

ENGINES = ("mujoco", "pybullet")


def installed_engines() -> tuple[str, ...]:
    """The engines this installation can run: PyBullet is optional (atd/sim/optional.py)."""
    from atd.sim.optional import pybullet_installed

    return ENGINES if pybullet_installed() else ("mujoco",)


def variants(robot: str | None = None) -> list[tuple[str, str]]:
    """Every (robot, arm) model the installed factories offer, or only `robot`'s."""
    return [(name, arm.name) for name, entry in installed().items() if robot in (None, name)
            for arm in entry.load().arms]


def load_description(robot: str, arm: str | None = None) -> RobotDescription:
    """The physical description of an installed robot (and arm), as its factory knows it.

    Raises UnknownRobot for a robot nobody installed, ValueError for an arm it lacks."""
    return create(robot, arm).robot


def make_robot(description: RobotDescription, scene: Scene | None = None, engine: str = "mujoco", seed: int = 0,
               window: bool = False, belief: RobotDescription | None = None) -> SimRobot:
    """A simulated robot in `scene` (default: a 5 cm box in the work area) on the named
    engine; `window` opens the engine's interactive window (it needs a display). `belief` is
    what the robot knows of itself where that differs from `description` (see `SimRobot`).
    A scene that asks to settle has settled when it is returned (`robot.settling`)."""
    return make_arms((description,), scene, engine, seed, window, (belief,))[0]


def make_arms(descriptions: tuple[RobotDescription, ...], scene: Scene | None = None, engine: str = "mujoco",
              seed: int = 0, window: bool = False, beliefs: tuple[RobotDescription | None, ...] | None = None
              ) -> tuple[SimRobot, ...]:
    """Several arms of one robot (a description each, as its factory gives them) in one world,
    each behind its own robot interface; stepping the first steps them all. The first arm
    starts at its home, the others `parked` where their descriptions say; the k-th arm's sensor noise
    is drawn from `seed + k`."""
    engine_robot = _engine_robot(engine)
    scene = scene if scene is not None else box_scene()
    beliefs = beliefs or (None,) * len(descriptions)
    if len(descriptions) > 1:
        from atd.sim.two_arms import parked

        descriptions = (descriptions[0],) + tuple(parked(d) for d in descriptions[1:])
        beliefs = (beliefs[0],) + tuple(parked(b) if b else None for b in beliefs[1:])
    first = engine_robot(descriptions[0], scene, seed, window, beliefs[0], others=descriptions[1:])
    try:
        arms = (first,) + tuple(first.arm(d, seed + k, b)
                                for k, (d, b) in enumerate(zip(descriptions[1:], beliefs[1:]), 1))
        if scene.settle:
            first.settle()
    except BaseException:
        first.close()
        raise
    return arms


def _engine_robot(engine: str) -> type[SimRobot]:
    """The robot class of the named engine (ValueError for one this installation lacks)."""
    if engine == "mujoco":
        from atd.sim.mujoco_engine import MujocoRobot

        return MujocoRobot
    if engine == "pybullet":
        if engine not in installed_engines():
            from atd.sim.optional import pybullet_missing

            raise ValueError(pybullet_missing("the pybullet engine"))
        from atd.sim.pybullet_engine import PybulletRobot

        return PybulletRobot
    raise ValueError(f"unknown engine '{engine}'; use one of {', '.join(ENGINES)}")
