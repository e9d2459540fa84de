"""Finding factories: the `atd.factories` entry-point group, so any installed package can add a robot.

A package adds a robot by declaring, in its own pyproject.toml:

    [project.entry-points."atd.factories"]
    myrobot = "mypackage.factory:MyRobotFactory"

The three built-in robots are declared the same way in this project's pyproject.toml. They
are also listed here so that a source checkout works before it is (re)installed; a test
keeps the two lists equal.
"""

from __future__ import annotations

from dataclasses import dataclass
from importlib import import_module
from importlib.metadata import entry_points
from pathlib import Path

from factories.base import Factory

GROUP = "atd.factories"
BUILTIN = {
    "baxter": "factories.baxter.factory:BaxterFactory",
    "melfa": "factories.melfa.factory:MelfaFactory",
    "tombatossals": "factories.tombatossals.factory:TombatossalsFactory",
}


class UnknownRobot(LookupError):
    pass


@dataclass(frozen=True)
class Installed:
    name: str
    target: str  # "module:Class"

    def load(self) -> type[Factory]:
        module, _, attr = self.target.partition(":")
        factory = getattr(import_module(module), attr)
        if not (isinstance(factory, type) and issubclass(factory, Factory)):
            raise TypeError(f"entry point '{self.name}' = '{self.target}' is not a factories.base.Factory subclass")
        return factory


def installed() -> dict[str, Installed]:
    """Every robot that can be translated for, by name, sorted."""
    found = {name: Installed(name, target) for name, target in BUILTIN.items()}
    for ep in entry_points(group=GROUP):
        found[ep.name] = Installed(ep.name, ep.value)
    return dict(sorted(found.items()))


def factory_class(robot: str) -> type[Factory]:
    robots = installed()
    if robot not in robots:
        raise UnknownRobot(f"no robot '{robot}' is installed; installed: {', '.join(robots)}")
    return robots[robot].load()


def create(robot: str, arm: str | None = None, config: Path | None = None, grasp: str = "robust") -> Factory:
    """A ready factory; raises UnknownRobot, ValueError (bad arm or grasp) or factories.config.ConfigError."""
    return factory_class(robot)(arm=arm, config=config, grasp=grasp)
