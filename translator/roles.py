"""Binding a task's roles to a robot's arms (docs/atd-format.md, *Roles*).

The task names the arms it needs by their part in it (`holder`, `worker`); the robot's
arms have the names its factory gives them. Roles are bound in the task's order: one
the user binds (`--role holder=left`) to that arm, the rest to the chosen arm first and
then to the robot's other arms in its own order. A task needing more arms than the robot
has is refused at the first role left without one.
"""

from __future__ import annotations

from typing import Mapping

from atd.model.diagnostics import Diagnostic, error
from atd.model.task import Task
from factories.base import Factory


def bind_roles(task: Task, factory: Factory, wanted: Mapping[str, str] | None = None
               ) -> tuple[dict[str | None, Factory], list[Diagnostic]]:
    """Each role of `task` (None for a task that declares none) -> the factory on its arm;
    or the diagnostics saying why the robot cannot give the task its arms. ValueError when
    `wanted` binds a role the task lacks, an arm the robot lacks, or one arm twice."""
    wanted = dict(wanted or {})
    _check_wanted(task, factory, wanted)
    if not task.roles:
        return {None: factory}, []
    arms = [factory.arm.name] + [a.name for a in factory.arms if a is not factory.arm]
    free = [a for a in arms if a not in wanted.values()]
    binding: dict[str | None, Factory] = {}
    problems = []
    for role in task.roles:
        if role.name in binding:
            continue
        arm = wanted.get(role.name) or (free.pop(0) if free else None)
        if arm is None:
            needed = ", ".join(r.name for r in task.roles)
            problems.append(error(
                "TRN005", f"{factory.name}: cannot give role '{role.name}' an arm: the {factory.name} has "
                f"{len(factory.arms)} arm{'s' * (len(factory.arms) != 1)} ({', '.join(arms)}) and the task needs "
                f"{len(task.roles)} ({needed})", role.loc,
                f"translate it for a robot with {len(task.roles)} arms (`atd robots list`), or give the states of "
                f"'{role.name}' to another role"))
            continue
        binding[role.name] = factory.on_arm(arm)
    return binding, problems


def _check_wanted(task: Task, factory: Factory, wanted: dict[str, str]) -> None:
    """A binding asked for names a role of the task and an arm of the robot, each arm once."""
    roles = [r.name for r in task.roles]
    arms = [a.name for a in factory.arms]
    for role, arm in wanted.items():
        if role not in roles:
            raise ValueError(f"role binding {role}={arm}: the task has no role '{role}' (its roles: "
                             f"{', '.join(roles) or 'none; it uses one arm, chosen with --arm'})")
        if arm not in arms:
            raise ValueError(f"role binding {role}={arm}: the {factory.name} has no arm '{arm}' (its arms: "
                             f"{', '.join(arms)})")
    doubled = sorted({arm for arm in wanted.values() if list(wanted.values()).count(arm) > 1})
    if doubled:
        raise ValueError(f"role bindings give the {factory.name}'s arm '{doubled[0]}' to several roles; one arm "
                         "per role")
