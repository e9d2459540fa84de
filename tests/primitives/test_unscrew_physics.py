"""The unscrew (thesis 3.3.6) in physics: examples/unscrew_fixture.xml on Tombatossals' SDH2,
the jam jar of its world file standing in a fixture, the cap then put on the table (thesis
Fig. 3.19). The task's verdict comes from the robot's own sensors; the simulator's truth (the
cap off its thread, resting on the table) judges it."""

from __future__ import annotations

from pathlib import Path

from atd.model import load_task
from atd.runtime.session import Run, world_scene
from factories.registry import create
from translator import translate

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_the_sdh2_unscrews_the_jam_jars_cap_puts_it_on_the_table_and_the_simulator_agrees() -> None:
    task, _ = load_task(EXAMPLES / "unscrew_fixture.xml")
    factory = create("tombatossals", arm="left")
    estd = translate(task, factory).estd
    caps: dict = {}
    run = Run(estd, factory, engine="mujoco", scene=world_scene(estd, EXAMPLES / "unscrew_fixture.world.toml", 0))
    outcome = run.execute(afterwards=lambda robot: caps.update(robot.caps()))
    assert outcome.succeeded and outcome.end_state == "cap_on_table", outcome.summary
    assert caps["jar"].free and caps["jar"].rests == "table", caps
    ends = [c["reason"] for r in run.trace.records if r["type"] == "event" for c in r["conditions"] if "reason" in c]
    assert any(reason.startswith("cap off after") for reason in ends), ends
