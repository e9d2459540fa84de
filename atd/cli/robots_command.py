"""`atd robots list` and `atd robots show R`: the installed factories and their mapping tables.

(Not `robots.py`: that name would shadow the `robots` click group that `atd.cli` exports.)
"""

from __future__ import annotations

import json

import click

from atd.cli.app import robots
from atd.cli.translate import make_factory
from atd.model.controllers import format_value
from atd.model.task import Event, State, Task, Transition
from atd.model.vocabulary import FIRED_BY, EventType, StateType
from atd.model.estd import describe
from factories.base import Factory, MappingContext, Unmappable
from factories.beside import description_file
from factories.registry import installed


FORMAT_OPTION = click.option("--format", "fmt", type=click.Choice(["text", "json"]), default="text", show_default=True,
                             help="as text, or as one JSON document")


def robot_entry(name: str, factory: Factory) -> dict:
    """What `atd robots list` says of one robot, as data."""
    caps = factory.capabilities
    return {"name": name, "description": factory.description, "arms": [a.name for a in factory.arms],
            "default_arm": factory.arms[0].name, "primitives": sorted(p.value for p in caps.primitives),
            "hand_shapes": sorted(s.value for s in caps.hand_shapes), "events": sorted(e.value for e in caps.events)}


@robots.command("list")
@FORMAT_OPTION
def list_robots(fmt: str = "text") -> None:
    """Every installed robot with its arms and capabilities."""
    entries = [robot_entry(name, entry.load()()) for name, entry in installed().items()]
    if fmt == "json":
        click.echo(json.dumps(entries, indent=2))
        return
    for robot in entries:
        click.echo(f"{robot['name']}: {robot['description']}")
        click.echo(f"  arms:        {', '.join(robot['arms'])} (default {robot['default_arm']})")
        click.echo(f"  primitives:  {', '.join(robot['primitives'])}")
        click.echo(f"  hand shapes: {', '.join(robot['hand_shapes'])}")
        click.echo(f"  events:      {', '.join(robot['events'])}")


def event_rows(factory: Factory) -> list[tuple[str, str]]:
    """How each abstract event is detected, read off the factory itself (so it cannot go stale)."""
    rows = []
    for origin_type in (StateType.MOVE, *sorted(factory.primitives - {StateType.MOVE})):
        origin = State(name="origin", type=origin_type)
        task = Task(states=(origin, State(name="next", type=StateType.SUCCESS)))
        for event in EventType:
            if event in FIRED_BY and origin_type not in FIRED_BY[event]:
                continue  # fired only by states of other types (perception, sub-tasks)
            edge = Transition(origin="origin", destination="next", events=(Event(type=event),))
            try:
                text = describe(factory.map_event(event, 5.0, edge, MappingContext(task)), thresholds=True)
            except Unmappable as exc:
                text = f"cannot: {exc.reason}"
            label = event.value if origin_type is StateType.MOVE else f"{event.value} (leaving {origin_type.value})"
            if origin_type is StateType.MOVE or text not in {r[1] for r in rows if r[0].split()[0] == event.value}:
                rows.append((label, text))
    return rows


def mapping_table(factory: Factory) -> str:
    """The robot's mapping table in the columns of thesis Tables 7.3 and 7.4, as Markdown."""
    lines = ["| Abstract | Concrete primitive | Extra parameters | Control and sensors |", "|---|---|---|---|"]
    lines += [f"| {r.abstract} | {r.concrete} | {r.extra_parameters} | {r.control_and_sensors} |"
              for r in factory.node_table]
    return "\n".join(lines)


def robot_sheet(factory: Factory) -> dict:
    """What `atd robots show` says of one robot and arm, as data."""
    return {
        "name": factory.name, "description": factory.description, "arm": factory.arm.name,
        "arms": [{"name": a.name, "description": a.description, "hand": a.hand.kind,
                  "sensors": [{"name": s.name, "kind": s.kind.value} for s in a.sensors]} for a in factory.arms],
        "base": list(factory.robot.base.xyz), "reach_checked_on": str(description_file(type(factory))),
        "primitives": [{"abstract": r.abstract, "concrete": r.concrete, "extra_parameters": r.extra_parameters,
                        "control_and_sensors": r.control_and_sensors} for r in factory.node_table],
        "events": [{"event": label, "detected_by": text} for label, text in event_rows(factory)],
        "config": {"controllers": {name: dict(sorted(params.items()))
                                   for name, params in sorted(factory.config.controllers.items())},
                   "conditions": {f"{event}/{kind}": dict(sorted(params.items()))
                                  for (event, kind), params in sorted(factory.config.conditions.items())}},
    }


@robots.command("show")
@click.argument("robot")
@click.option("--arm", default=None, help="which arm (default: the robot's first)")
@FORMAT_OPTION
def show(robot: str, arm: str | None, fmt: str) -> None:
    """Print ROBOT's description, arms, mapping table, event conditions and config values."""
    factory = make_factory(robot, arm, None)
    if fmt == "json":
        click.echo(json.dumps(robot_sheet(factory), indent=2))
        return
    click.echo(f"{factory.name}: {factory.description}\n")
    for a in factory.arms:
        click.echo(f"arm '{a.name}': {a.description} ({a.hand.kind} hand)")
        click.echo(f"  sensors: {', '.join(f'{s.name} ({s.kind.value})' for s in a.sensors)}")
    base = factory.robot.base.xyz
    click.echo(f"  placed with its base at ({base[0]:g}, {base[1]:g}, {base[2]:g}) in the ATD world frame; "
               f"reach is checked on {description_file(type(factory))}: by inverse kinematics with the hand pointing down, "
               f"by rehearsing the arm's motion from home with the hand turned as a <pose> turns it")
    click.echo(f"\nprimitives ({factory.arm.name} arm):\n{mapping_table(factory)}\n")
    click.echo("events:")
    for label, text in event_rows(factory):
        click.echo(f"  {label}: {text}")
    click.echo("\nconfig (overrides of the thesis defaults):")
    for name, params in sorted(factory.config.controllers.items()):
        click.echo(f"  {name}: {', '.join(f'{k}={format_value(v)}' for k, v in sorted(params.items()))}")
    for (event, kind), params in sorted(factory.config.conditions.items()):
        click.echo(f"  {event}/{kind}: {', '.join(f'{k}={format_value(v)}' for k, v in sorted(params.items()))}")
