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
from atd.model.toml_lines import TomlLines
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


def _table(at: TomlLines, where: str, path: tuple[str, ...], value: object) -> dict:
    """A table of the config, or ConfigError at its line when a plain value stands there."""
    if not isinstance(value, dict):
        raise ConfigError(f"{at.find(path, where)}: [{'.'.join(path)}] must be a table, not {value!r}")
    return value


def _params(at: TomlLines, where: str, table: tuple[str, ...], specs: dict[str, ParamSpec],
            values: object) -> Params:
    params: Params = {}
    for name, value in _table(at, where, table, values).items():
        place = f"{at.find(table + (name,), where)}: [{'.'.join(table)}]"
        spec = specs.get(name)
        if spec is None or not spec.tunable:
            tunable = ", ".join(sorted(n for n, s in specs.items() if s.tunable)) or "none"
            why = "comes from the task" if spec is not None else "is not a parameter here"
            raise ConfigError(f"{place} '{name}' {why}; tunable parameters: {tunable}")
        try:
            params[name] = coerce_value(spec, value)
        except ValueError as exc:
            raise ConfigError(f"{place} {name}: {exc}") from None
    return params


def load_config(path: Path, robot: str) -> RobotConfig:
    """The part of a config file that concerns `robot` (empty when the file does not mention it).
    Every refusal names the file and the line, as a diagnostic does."""
    try:
        text = read_capped(Path(path), MAX_CONFIG_BYTES).decode("utf-8")
        data = tomllib.loads(text)
    except InputError as exc:
        raise ConfigError(f"{path}: cannot read config file: {exc}") from None
    except UnicodeDecodeError:
        raise ConfigError(f"{path}: not UTF-8 text; save the config file as UTF-8") from None
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{path}: not valid TOML: {exc}") from None
    at, where = TomlLines(text), str(path)
    section = _table(at, where, (robot,), data.get(robot, {}))
    unknown = set(section) - {"controllers", "conditions"}
    if unknown:
        first = sorted(unknown)[0]
        raise ConfigError(f"{at.find((robot, first), where)}: [{robot}.{first}] is not a section; use "
                          f"[{robot}.controllers.NAME] or [{robot}.conditions.EVENT.KIND]")
    controllers = {}
    for name, values in _table(at, where, (robot, "controllers"), section.get("controllers", {})).items():
        table = (robot, "controllers", name)
        if name not in CONTROLLERS:
            raise ConfigError(f"{at.find(table, where)}: [{'.'.join(table)}] names no controller; known: "
                              f"{', '.join(sorted(CONTROLLERS))}")
        controllers[name] = _params(at, where, table, dict(CONTROLLERS[name].params), values)
    conditions = {}
    for event, kinds in _table(at, where, (robot, "conditions"), section.get("conditions", {})).items():
        if event not in EventType.__members__.values():
            raise ConfigError(f"{at.find((robot, 'conditions', event), where)}: [{robot}.conditions.{event}] names "
                              f"no abstract event; known: {', '.join(e.value for e in EventType)}")
        for kind, values in _table(at, where, (robot, "conditions", event), kinds).items():
            table = (robot, "conditions", event, kind)
            if kind not in CONDITIONS:
                raise ConfigError(f"{at.find(table, where)}: [{'.'.join(table)}] names no condition kind; known: "
                                  f"{', '.join(sorted(CONDITIONS))}")
            conditions[(event, kind)] = _params(at, where, table, dict(CONDITIONS[kind].params), values)
    return RobotConfig(controllers, conditions)
