"""Fixtures for the simulated robots: every robot variant, and engines that close after use."""

from __future__ import annotations

from typing import Callable, Iterator

import pytest

from atd.sim import ENGINES, load_description, make_robot
from atd.sim.scene import Scene
from atd.sim.simrobot import SimRobot
from factories.description import RobotDescription

@pytest.fixture(params=ENGINES)
def engine(request) -> str:
    return request.param


@pytest.fixture
def melfa() -> RobotDescription:
    return load_description("melfa")


@pytest.fixture
def robot_of() -> Iterator[Callable[..., SimRobot]]:
    """make_robot, closing every robot it made when the test ends."""
    made: list[SimRobot] = []

    def make(description: RobotDescription, engine: str, scene: Scene | None = None, seed: int = 0) -> SimRobot:
        robot = make_robot(description, scene, engine, seed)
        made.append(robot)
        return robot

    yield make
    for robot in made:
        robot.close()


@pytest.fixture
def run() -> Callable[[SimRobot, float], None]:
    """Step a robot, commands unchanged, for some seconds of simulated time."""

    def step_for(robot: SimRobot, seconds: float) -> None:
        for _ in range(round(seconds / robot.info.control_period)):
            robot.step()

    return step_for
