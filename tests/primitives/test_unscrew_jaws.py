"""The unscrew on a parallel gripper in physics: examples/unscrew_fixture_jaws.xml on the
Melfa in MuJoCo, the jam jar of examples/unscrew_fixture.world.toml in its fixture. The jaws
grip the cap, the last wrist joint twists it; the task's verdict comes from the robot's own
sensors, and the simulator's truth judges it. A cap whose thread will not turn ends through
`error`, saying why, with the cap still on by truth."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

import atd.sim.library as objects
from atd.model import load_task
from atd.runtime.session import Run, world_scene
from factories.registry import create
from translator import translate

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
STUCK_TORQUE = 3.0  # N m: ten times what 10 N on each of the Melfa's pads can turn on a 60 mm cap


def _run(max_pinches: int | None = None) -> tuple[object, dict, list[str]]:
    task, _ = load_task(EXAMPLES / "unscrew_fixture_jaws.xml")
    if max_pinches is not None:
        state = task.states_by_name["unscrew_cap"]
        state = state.model_copy(update={"parameters": {**state.parameters, "max_pinches": str(max_pinches)}})
        task = task.model_copy(update={"states": tuple(state if s.name == "unscrew_cap" else s for s in task.states)})
    factory = create("melfa")
    estd = translate(task, factory).estd
    caps: dict = {}
    run = Run(estd, factory, engine="mujoco", scene=world_scene(estd, EXAMPLES / "unscrew_fixture.world.toml", 0))
    outcome = run.execute(afterwards=lambda robot: caps.update(robot.caps()))
    reasons = [c["reason"] for r in run.trace.records if r["type"] == "event" for c in r["conditions"] if "reason" in c]
    return outcome, caps, reasons


def test_the_melfa_twists_the_jam_jars_cap_off_with_its_wrist_and_the_simulator_agrees() -> None:
    outcome, caps, reasons = _run()
    assert outcome.succeeded and outcome.end_state == "cap_off", outcome.summary
    assert caps["jar"].free and caps["jar"].rests == "held", caps
    assert any(reason.startswith("cap off after") for reason in reasons), reasons


def test_a_stuck_cap_ends_through_error_with_the_cap_still_on(monkeypatch: pytest.MonkeyPatch) -> None:
    capped = objects._screw_capped()
    stuck = tuple(dataclasses.replace(o, thread=dataclasses.replace(o.thread, torque=STUCK_TORQUE))
                  if o.name == "jam_jar" else o for o in capped)
    monkeypatch.setattr(objects, "_screw_capped", lambda: stuck)
    outcome, caps, reasons = _run(max_pinches=2)
    assert not outcome.succeeded and outcome.end_state == "cap_on", outcome.summary
    assert any(r.startswith("the cap not felt to come off after 2 pinches") for r in reasons), reasons
    assert not caps["jar"].free and caps["jar"].turned < 0.02, caps
