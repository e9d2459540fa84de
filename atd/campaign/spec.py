"""A campaign spec: a TOML file naming tasks, robots, engines, grasp modes, objects,
perturbation models, trials per cell and a base seed.

Read like an ATD: every problem at once, each with the file:line it stands on, a stable
code and a hint, so a typo in a 3,000-trial campaign is found before the first trial.
"""

from __future__ import annotations

import hashlib
import math
import re
import tomllib
from pathlib import Path
from typing import Annotated, Literal, Union

from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator

from atd.campaign.checks import PLAIN_NAME, check_entries
from atd.campaign.fields import Count, Number, StrictTable, within
from atd.campaign.perturbation import CELL_KEYS, MODELS, NoPerturbation, Perturbation
from atd.campaign.record import DIMENSIONS, TASK_OBJECT
from atd.campaign.sources import digests
from atd.model import ranges
from atd.model.diagnostics import Diagnostic, did_you_mean, error
from atd.model.files import InputError, read_capped, real_path
from atd.model.task import Location
from atd.model.toml_lines import TomlLines

GRASP_MODES = ("naive", "robust")
JUDGES = ("lift", "place", "box", "cap")
SPEC_CAP = 1 << 20  # bytes: a spec is a page of TOML

TRIAL_BUDGET = ranges.Range(0.0, 3600.0, "s", low_open=True)


class TaskEntry(StrictTable):
    file: str
    judge: Literal["lift", "place", "box", "cap"] | None = None  # None: chosen from the task's states and the spec
    fixture: bool = False  # its screw-capped objects stand in a clamp on the table (a one-arm task)


class RobotEntry(StrictTable):
    name: str
    arms: tuple[str, ...] = ()  # empty: the robot's default arm


class WorldDraw(StrictTable):
    """A world drawn afresh for every trial (thesis 3.4.3): `objects` library objects, drawn
    from `from` (each once while there are enough), dropped at random poses into the task's
    container `into` (with a `clearance`, laid down resting that far from its walls) and
    settled by the physics; seeded by the trial."""

    model_config = ConfigDict(extra="forbid", frozen=True, populate_by_name=True)

    objects: Count = Field(ge=1, le=20, description="how many objects")
    into: str = Field(pattern=f"^{PLAIN_NAME.pattern}$", description="the task's container they are dropped into")
    from_: tuple[str, ...] = Field(alias="from", min_length=1, description="the library objects to draw from")
    clearance: Annotated[Number, within(ranges.CLEARANCE)] = Field(
        0.0, description="m: laid down resting this far from the walls instead of dropped (thesis 3.4.3's assumption)")

    @field_validator("from_")
    @classmethod
    def _known(cls, names: tuple[str, ...]) -> tuple[str, ...]:
        from atd.sim.library import library

        known = library()
        unknown = [n for n in names if n not in known]
        if unknown:
            raise ValueError(f"no object '{unknown[0]}' in the library; library objects: {', '.join(known)}")
        return names


class CampaignSpec(StrictTable):
    name: str = Field(pattern=f"^{PLAIN_NAME.pattern}$")
    base_seed: Count = Field(0, ge=0, lt=2**63)
    trials: Count = Field(10, ge=ranges.TRIALS.low, le=ranges.TRIALS.high, description="trials per cell")
    budget: Annotated[Number, within(TRIAL_BUDGET)] = Field(
        120.0, description="simulated seconds before the watchdog stops a trial")
    tasks: tuple[Union[str, TaskEntry], ...] = Field(min_length=1)
    robots: tuple[Union[str, RobotEntry], ...] = Field(min_length=1)
    engines: tuple[Literal["mujoco", "pybullet"], ...] = Field(("mujoco",), min_length=1)
    grasps: tuple[Literal["naive", "robust"], ...] = Field(("robust",), min_length=1)
    objects: tuple[str, ...] = Field((TASK_OBJECT,), min_length=1)
    perturbations: dict[str, Perturbation] = Field(default_factory=lambda: {"none": NoPerturbation(model="none")})
    world: WorldDraw | None = None  # None: the task's own objects (with the cell's object)

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

    def task_digests(self) -> dict[str, str]:
        """The digest of every file the spec's tasks are made of, as they are now."""
        return digests((self.task_path(e) for e in self.spec.task_entries), self.path.parent)


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
    found = check_entries(data, real_path(path).parent, where, lines)
    try:
        spec = CampaignSpec.model_validate(data)
    except ValidationError as exc:
        found += [_diagnostic(e, where, lines) for e in exc.errors()]
        # The spec's own by line; a task's errors (located in the task) keep their order, after them.
        return None, sorted(found, key=lambda d: d.loc.line if d.loc.file == where else math.inf)
    return LoadedSpec(spec=spec, path=real_path(path), text=text), found


def _diagnostic(e: dict, where: str, lines: TomlLines) -> Diagnostic:
    loc = tuple(p for p in e["loc"] if p not in ("str", "TaskEntry", "RobotEntry"))
    if loc[:1] == ("perturbations",) and len(loc) > 1:
        return _perturbation_diagnostic(e, loc, where, lines)
    dotted = ".".join(str(p) for p in loc)
    message = e["msg"].removeprefix("Value error, ")
    if e["type"] == "extra_forbidden":
        allowed = _allowed_keys(loc[:-1])
        return error("CMP010", f"unknown key '{dotted}'", lines.find(loc, where),
                     did_you_mean(str(loc[-1]), allowed) or f"known keys here: {', '.join(allowed)}")
    if e["type"] == "missing":
        return error("CMP011", f"'{dotted}' is required", lines.find(loc[:-1], where), f"add {loc[-1]} = ...")
    return error("CMP012", f"{dotted}: {message}", lines.find(loc, where), _hint(loc))


def _perturbation_diagnostic(e: dict, loc: tuple, where: str, lines: TomlLines) -> Diagnostic:
    """A perturbation table's problem, in terms of its model: pydantic puts the model's name
    in the location (`perturbations.p.approach.x`), and a parameter the model does not have
    is answered with the ones it has."""
    table = loc[:2]
    models = ", ".join(MODELS)
    if e["type"] == "union_tag_not_found":
        return error("CMP011", f"'{'.'.join(table)}.model' is required", lines.find(table, where),
                     f"add model = ..., one of {models}")
    if e["type"] == "union_tag_invalid":
        tag = str(e["ctx"]["tag"])
        return error("CMP012", f"{'.'.join(table)}.model: no perturbation model '{tag}'",
                     lines.find((*table, "model"), where), did_you_mean(tag, MODELS) or f"perturbation models: {models}")
    model = loc[2] if len(loc) > 2 and loc[2] in MODELS else None
    loc = table + loc[3:] if model else loc
    dotted = ".".join(str(p) for p in loc)
    if model and e["type"] == "extra_forbidden":
        key = str(loc[-1])
        params = [n for n in MODELS[model].model_fields if n not in ("model", *CELL_KEYS)]
        owners = [m for m, kind in MODELS.items() if key in kind.model_fields and key not in ("model", *CELL_KEYS)]
        hint = f"the '{model}' model's parameters: {', '.join(params) or 'none'}" + (
            f" ('{key}' belongs to {', '.join(repr(m) for m in owners)})" if owners else "")
        return error("CMP010", f"unknown key '{dotted}': perturbation model '{model}' has no parameter '{key}'",
                     lines.find(loc, where), hint)
    return error("CMP012", f"{dotted}: {e['msg'].removeprefix('Value error, ')}", lines.find(loc, where), None)


def _allowed_keys(parent: tuple) -> list[str]:
    if not parent:
        return sorted(CampaignSpec.model_fields)
    if parent[0] == "tasks":
        return sorted(TaskEntry.model_fields)
    if parent[0] == "robots":
        return sorted(RobotEntry.model_fields)
    if parent[0] == "world":
        return sorted(f.alias or n for n, f in WorldDraw.model_fields.items())
    return []


def _hint(loc: tuple) -> str | None:
    if loc and loc[0] == "engines":
        return "engines are 'mujoco' and 'pybullet'"
    if loc and loc[0] == "grasps":
        return "grasp modes are 'naive' and 'robust'"
    return None


__all__ = ["DIMENSIONS", "GRASP_MODES", "JUDGES", "TASK_OBJECT", "CampaignSpec", "LoadedSpec", "WorldDraw", "load_spec"]
