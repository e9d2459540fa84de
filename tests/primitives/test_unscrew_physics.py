"""The unscrew (thesis 3.3.6) in physics: examples/unscrew_fixture.xml on Tombatossals' SDH2,
the jam jar of its world file standing in a fixture, the cap then put on the table (thesis
Fig. 3.19). The task's verdict comes from the robot's own sensors; the simulator's truth (the
cap off its thread, resting on the table) judges it."""

from __future__ import annotations

from pathlib import Path

import pytest

from atd.model import load_task
from atd.runtime.executor import Outcome
from atd.runtime.session import Run, world_scene
from factories.registry import create
from translator import translate

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _run(arm: str, engine: str, budget: float = 300.0) -> tuple[Run, Outcome, dict]:
    """The example on one arm of Tombatossals in one engine, stopped after `budget` s; the caps as it ended."""
    task, _ = load_task(EXAMPLES / "unscrew_fixture.xml")
    factory = create("tombatossals", arm=arm)
    estd = translate(task, factory).estd
    caps: dict = {}
    run = Run(estd, factory, engine=engine, scene=world_scene(estd, EXAMPLES / "unscrew_fixture.world.toml", 0),
              budget=budget)
    outcome = run.execute(afterwards=lambda robot: caps.update(robot.caps()))
    return run, outcome, caps


@pytest.mark.parametrize("engine", ["mujoco", "pybullet"])
def test_the_sdh2_unscrews_the_jam_jars_cap_puts_it_on_the_table_and_the_simulator_agrees(engine: str) -> None:
    run, outcome, caps = _run("left", engine)
    assert outcome.succeeded and outcome.end_state == "cap_on_table", outcome.summary
    assert caps["jar"].free and caps["jar"].rests == "table", caps
    ends = [c["reason"] for r in run.trace.records if r["type"] == "event" for c in r["conditions"] if "reason" in c]
    assert any(reason.startswith("cap off after") for reason in ends), ends


def test_the_barretts_pinch_takes_the_cap_and_its_twist_turns_it_in_pybullet() -> None:
    """Tombatossals' right arm, at the example's heights: the pads' tips meet the 60 mm cap 2 mm
    below the TCP and press it with the grasp force, and the first twist turns it (8 s of the
    run; the whole run takes the cap off after 4 twists, docs/writing-a-primitive.md)."""
    _, outcome, caps = _run("right", "pybullet", budget=8.0)
    assert "unscrew_cap" in outcome.summary, outcome.summary  # still unscrewing when the 8 s ran out
    assert caps["jar"].turned > 0.3 and not caps["jar"].free, caps  # of the quarter turn (1.57 rad) it takes
