"""Per-robot parameter overrides from a small TOML file.

Each robot ships `factories/<robot>/config.toml` with the values that differ from the
thesis defaults of `atd.model.controllers` (e.g. Baxter's raised thresholds for its
noisy virtual force sensor); `atd translate --config FILE` layers a user file on top.
The format, one table per controller and one per (event, condition kind):

    [melfa.controllers.close_until_force]
    grasp_force = 20.0

    [melfa.conditions.grasp_stable.tactile_force_above]
    force_threshold = 8.0

Only tunable parameters (those with a default) may be set: targets and shapes come from
the task, never from a config file.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from atd.model.controllers import CONDITIONS, CONTROLLERS, ParamSpec, ParamValue, coerce_value
from atd.model.files import InputError, read_capped
from atd.model.vocabulary import EventType

Params = dict[str, ParamValue]
MAX_CONFIG_BYTES = 1 << 20  # a config sets a few dozen values


class ConfigError(Exception):
    """A config file that cannot be used; the message names the file, the table and the fix."""


@dataclass(frozen=True)
class RobotConfig:
    controllers: dict[str, Params] = field(default_factory=dict)  # controller name -> params
    conditions: dict[tuple[str, str], Params] = field(default_factory=dict)  # (event, kind) -> params

    def over(self, base: RobotConfig) -> RobotConfig:
        """This config layered on top of `base`."""
        controllers = {k: dict(v) for k, v in base.controllers.items()}
        for name, params in self.controllers.items():
            controllers.setdefault(name, {}).update(params)
        conditions = {k: dict(v) for k, v in base.conditions.items()}
        for key, params in self.conditions.items():
            conditions.setdefault(key, {}).update(params)
        return RobotConfig(controllers, conditions)


def _params(file: Path, table: str, specs: dict[str, ParamSpec], values: object) -> Params:
    if not isinstance(values, dict):
        raise ConfigError(f"{file}: [{table}] must be a table of parameter = value")
    params: Params = {}
    for name, value in values.items():
        spec = specs.get(name)
        if spec is None or not spec.tunable:
            tunable = ", ".join(sorted(n for n, s in specs.items() if s.tunable)) or "none"
            why = "comes from the task" if spec is not None else "is not a parameter here"
            raise ConfigError(f"{file}: [{table}] '{name}' {why}; tunable parameters: {tunable}")
        try:
            params[name] = coerce_value(spec, value)
        except ValueError as exc:
            raise ConfigError(f"{file}: [{table}] {name}: {exc}") from None
    return params


def load_config(path: Path, robot: str) -> RobotConfig:
    """The part of a config file that concerns `robot` (empty when the file does not mention it)."""
    try:
        data = tomllib.loads(read_capped(Path(path), MAX_CONFIG_BYTES).decode("utf-8"))
    except InputError as exc:
        raise ConfigError(f"{path}: cannot read config file: {exc}") from None
    except UnicodeDecodeError:
        raise ConfigError(f"{path}: not UTF-8 text; save the config file as UTF-8") from None
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{path}: not valid TOML: {exc}") from None
    section = data.get(robot, {})
    unknown = set(section) - {"controllers", "conditions"}
    if unknown:
        raise ConfigError(f"{path}: [{robot}.{sorted(unknown)[0]}] is not a section; use "
                          f"[{robot}.controllers.NAME] or [{robot}.conditions.EVENT.KIND]")
    controllers = {}
    for name, values in section.get("controllers", {}).items():
        if name not in CONTROLLERS:
            raise ConfigError(f"{path}: [{robot}.controllers.{name}] names no controller; known: "
                              f"{', '.join(sorted(CONTROLLERS))}")
        controllers[name] = _params(path, f"{robot}.controllers.{name}", dict(CONTROLLERS[name].params), values)
    conditions = {}
    for event, kinds in section.get("conditions", {}).items():
        if event not in EventType.__members__.values():
            raise ConfigError(f"{path}: [{robot}.conditions.{event}] names no abstract event; known: "
                              f"{', '.join(e.value for e in EventType)}")
        for kind, values in kinds.items():
            if kind not in CONDITIONS:
                raise ConfigError(f"{path}: [{robot}.conditions.{event}.{kind}] names no condition kind; known: "
                                  f"{', '.join(sorted(CONDITIONS))}")
            table = f"{robot}.conditions.{event}.{kind}"
            conditions[(event, kind)] = _params(path, table, dict(CONDITIONS[kind].params), values)
    return RobotConfig(controllers, conditions)
