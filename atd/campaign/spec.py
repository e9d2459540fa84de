"""A campaign spec: a TOML file naming tasks, robots, engines, grasp modes, objects,
perturbation models, trials per cell and a base seed.

Read like an ATD: every problem at once, each with the file:line it stands on, a stable
code and a hint, so a typo in a 3,000-trial campaign is found before the first trial.
"""

from __future__ import annotations

import hashlib
import re
import tomllib
from pathlib import Path
from typing import Annotated, Literal, Union

from pydantic import BaseModel, ConfigDict, Field, Strict, ValidationError, ValidationInfo, field_validator

from atd.campaign.perturbation import PERTURBATIONS
from atd.campaign.record import DIMENSIONS
from atd.model import ranges
from atd.model.diagnostics import Diagnostic, did_you_mean, error
from atd.model.files import InputError, read_capped, real_path
from atd.model.task import Location
from atd.model.toml_lines import TomlLines

GRASP_MODES = ("naive", "robust")
JUDGES = ("lift", "place")
TASK_OBJECT = "task"  # the object dimension's value for the ATD's own object
SPEC_CAP = 1 << 20  # bytes: a spec is a page of TOML


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


# Numbers as TOML writes them: an integer may stand for a float, but `true` is not 1 and 2.0 is not a count.
Number = Annotated[float, Strict()]
Count = Annotated[int, Strict()]


class TaskEntry(_Strict):
    file: str
    judge: Literal["lift", "place"] | None = None  # None: chosen from the task's states


class RobotEntry(_Strict):
    name: str
    arms: tuple[str, ...] = ()  # empty: the robot's default arm


class Perturbation(_Strict):
    """One named perturbation model with its parameters; see `atd.campaign.perturbation`."""

    model: Literal["none", "approach", "object_pose", "object_physics", "sensors"]
    translation: Number = Field(0.05, ge=0, le=0.2, description="approach: ± m per axis")
    rotation: Number = Field(15.0, ge=0, le=90, description="approach: ± degrees about each axis")
    x: Number = Field(0.03, ge=0, le=0.2, description="object_pose: ± m along x")
    y: Number = Field(0.03, ge=0, le=0.2, description="object_pose: ± m along y")
    yaw: Number = Field(20.0, ge=0, le=180, description="object_pose: ± degrees about z")
    mass: tuple[Number, Number] = Field((0.5, 2.0), description="object_physics: mass scale range")
    friction: tuple[Number, Number] = Field((0.5, 1.5), description="object_physics: friction scale range")
    noise: tuple[Number, Number] = Field((1.0, 3.0), description="sensors: noise scale range")
    bias: tuple[Number, Number] = Field((0.0, 2.0), description="sensors: bias scale range")

    @field_validator("mass", "friction", "noise", "bias")
    @classmethod
    def _range(cls, value: tuple[float, float], info: ValidationInfo) -> tuple[float, float]:
        allowed = ranges.MASS_SCALE if info.field_name == "mass" else ranges.SCALE
        low, high = value
        problem = allowed.first_problem(value)
        if problem or low > high:
            raise ValueError(f"give [low, high] with low <= high, each in {allowed}: {problem or f'{low:g} > {high:g}'}")
        return value


class CampaignSpec(_Strict):
    name: str = Field(min_length=1, pattern=r"^[A-Za-z0-9_.-]+$")
    base_seed: Count = Field(0, ge=0, lt=2**63)
    trials: Count = Field(10, ge=ranges.TRIALS.low, le=ranges.TRIALS.high, description="trials per cell")
    budget: Number = Field(120.0, gt=0, le=3600, description="simulated seconds before the watchdog stops a trial")
    tasks: tuple[Union[str, TaskEntry], ...] = Field(min_length=1)
    robots: tuple[Union[str, RobotEntry], ...] = Field(min_length=1)
    engines: tuple[Literal["mujoco", "pybullet"], ...] = Field(("mujoco",), min_length=1)
    grasps: tuple[Literal["naive", "robust"], ...] = Field(("robust",), min_length=1)
    objects: tuple[str, ...] = Field((TASK_OBJECT,), min_length=1)
    perturbations: dict[str, Perturbation] = Field(default_factory=lambda: {"none": Perturbation(model="none")})

    @property
    def task_entries(self) -> tuple[TaskEntry, ...]:
        return tuple(TaskEntry(file=t) if isinstance(t, str) else t for t in self.tasks)

    @property
    def robot_entries(self) -> tuple[RobotEntry, ...]:
        return tuple(RobotEntry(name=r) if isinstance(r, str) else r for r in self.robots)


class LoadedSpec(BaseModel):
    """A spec with where it came from: task files are relative to it, and its text keys the store."""

    model_config = ConfigDict(frozen=True)

    spec: CampaignSpec
    path: Path
    text: str

    @property
    def digest(self) -> str:
        return hashlib.sha256(self.text.encode()).hexdigest()

    def task_path(self, entry: TaskEntry) -> Path:
        return real_path(self.path.parent / entry.file)


def load_spec(path: Path) -> tuple[LoadedSpec | None, list[Diagnostic]]:
    """The spec, or None with every problem found (CMP codes, located)."""
    where = str(path)
    try:
        text = read_capped(path, SPEC_CAP).decode("utf-8")
    except (InputError, UnicodeDecodeError) as exc:
        return None, [error("CMP001", f"cannot read the campaign spec: {exc}", Location(where, 0),
                            "give a readable UTF-8 TOML file")]
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        line = int(m.group(1)) if (m := re.search(r"line (\d+)", str(exc))) else 0
        return None, [error("CMP002", f"not valid TOML: {exc}", Location(where, line), "fix the TOML syntax")]
    lines = TomlLines(text)
    found = _check_names(data, real_path(path).parent, where, lines)
    try:
        spec = CampaignSpec.model_validate(data)
    except ValidationError as exc:
        found += [_diagnostic(e, where, lines) for e in exc.errors()]
        return None, sorted(found, key=lambda d: d.loc.line)
    return LoadedSpec(spec=spec, path=real_path(path), text=text), found


def _diagnostic(e: dict, where: str, lines: TomlLines) -> Diagnostic:
    loc = tuple(p for p in e["loc"] if p not in ("str", "TaskEntry", "RobotEntry"))
    dotted = ".".join(str(p) for p in loc)
    message = e["msg"]
    if e["type"] == "extra_forbidden":
        allowed = _allowed_keys(loc[:-1])
        return error("CMP010", f"unknown key '{dotted}'", lines.find(loc, where),
                     did_you_mean(str(loc[-1]), allowed) or f"known keys here: {', '.join(allowed)}")
    if e["type"] == "missing":
        return error("CMP011", f"'{dotted}' is required", lines.find(loc[:-1], where), f"add {loc[-1]} = ...")
    return error("CMP012", f"{dotted}: {message}", lines.find(loc, where), _hint(loc))


def _allowed_keys(parent: tuple) -> list[str]:
    if not parent:
        return sorted(CampaignSpec.model_fields)
    if parent[0] == "perturbations":
        return sorted(Perturbation.model_fields)
    if parent[0] == "tasks":
        return sorted(TaskEntry.model_fields)
    if parent[0] == "robots":
        return sorted(RobotEntry.model_fields)
    return []


def _hint(loc: tuple) -> str | None:
    field = str(loc[-1]) if loc else ""
    if loc and loc[0] == "engines":
        return "engines are 'mujoco' and 'pybullet'"
    if loc and loc[0] == "grasps":
        return "grasp modes are 'naive' and 'robust'"
    if field == "model":
        return f"perturbation models: {', '.join(PERTURBATIONS)}"
    return None


def _check_names(data: dict, folder: Path, where: str, lines: TomlLines) -> list[Diagnostic]:
    """What the schema cannot know: task files exist, robots and arms are installed,
    objects are in the library. Read from the raw TOML, so these are found together
    with the schema's own errors; entries of the wrong type are the schema's to report."""
    from factories.registry import installed

    found = []
    for i, entry in _entries(data, "tasks"):
        file = entry.get("file") if isinstance(entry, dict) else entry
        if isinstance(file, str) and not (folder / file).is_file():
            found.append(error("CMP020", f"no task file {real_path(folder / file)}", lines.find(("tasks", i), where),
                               "task files are relative to the spec"))
    robots = installed()
    for i, entry in _entries(data, "robots"):
        name = entry.get("name") if isinstance(entry, dict) else entry
        if not isinstance(name, str):
            continue
        if name not in robots:
            found.append(error("CMP021", f"no robot '{name}' is installed", lines.find(("robots", i), where),
                               did_you_mean(name, robots) or f"installed: {', '.join(robots)}"))
            continue
        arms = [a.name for a in robots[name].load().arms]
        for arm in entry.get("arms", ()) if isinstance(entry, dict) else ():
            if isinstance(arm, str) and arm not in arms:
                found.append(error("CMP022", f"robot '{name}' has no arm '{arm}'",
                                   lines.find(("robots", i, "arms"), where), f"its arms: {', '.join(arms)}"))
    named = [(i, o) for i, o in _entries(data, "objects") if isinstance(o, str) and o != TASK_OBJECT]
    if named:
        from atd.campaign.objects import library

        known = library()
        for i, name in named:
            if name not in known:
                found.append(error("CMP023", f"no object '{name}' in the library", lines.find(("objects", i), where),
                                   did_you_mean(name, known) or f"'{TASK_OBJECT}' or one of: {', '.join(known)}"))
    return found


def _entries(data: dict, key: str) -> list[tuple[int, object]]:
    value = data.get(key)
    return list(enumerate(value)) if isinstance(value, list) else []


__all__ = ["DIMENSIONS", "GRASP_MODES", "JUDGES", "TASK_OBJECT", "CampaignSpec", "LoadedSpec", "Perturbation",
           "load_spec"]
