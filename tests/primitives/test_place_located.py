"""A Baxter's place cannot weigh where its paddles hold the box, so its jaw grasp finds the
box's middle along them with the IR range sensor before closing: a box standing off along the
paddles is no longer set down that far from the target with the task saying it succeeded
(docs/pick-and-place.md)."""

from __future__ import annotations

from pathlib import Path

from atd.campaign.cells import parse_only, plans
from atd.campaign.spec import load_spec
from atd.campaign.trial import run_trial
from atd.model.vocabulary import EventType
from atd.sim.scene import box_scene
from primitives.blackboard import LOCATED_ALONG
from tests.primitives.conftest import EXAMPLES, Stage, both_done, execute, last_reasons, leaf, machine, simulated, use

SPEC = EXAMPLES / "campaigns" / "pick_and_place_displaced.toml"
# the trial of that campaign at seed 47129 (left arm, trial 2, MuJoCo) where the paddles closed
# 3.2 cm along them from the box's middle and the run said it succeeded, the box 3.5 cm off
SEED, TRIAL = 47129, 2


def test_a_baxter_puts_a_box_standing_off_along_its_paddles_on_the_target(tmp_path: Path) -> None:
    spec = tmp_path / "displaced.toml"
    spec.write_text(SPEC.read_text().replace("base_seed = 35", f"base_seed = {SEED}")
                    .replace('"../pick_and_place.xml"', f'"{(EXAMPLES / "pick_and_place.xml").as_posix()}"'))
    loaded, diagnostics = load_spec(spec)
    assert loaded is not None, diagnostics
    only = parse_only(("robot=baxter", "arm=left", "engine=mujoco"))
    [record] = [run_trial(plan) for plan in plans(loaded, only, TRIAL + 1) if plan.index == TRIAL]
    assert record.task_succeeded and record.judged_succeeded, (record.summary, record.judge_reason)
    assert record.measurements["distance"] < 0.01, record.judge_reason
    placed = [why for event in record.events if event["transition"].startswith("put_down->") for why in event["why"]]
    assert any("range sensor" in why for why in placed), placed

def test_a_place_that_cannot_weigh_after_a_grasp_that_did_not_see_the_object_fails() -> None:
    """Neither the wrist nor the grasp says where the object is in the hand: the place says
    so and fails, rather than put it down and claim the target."""
    estd = machine(Stage(use("place", target=(0.125, 0.1, 0.025), force_threshold=10.0, weigh_time=0.0),
                         use("squeeze", grasp_force=20.0, force_source="motor"), both_done()),
                   failures={"s0": (EventType.ERROR, leaf("arm_error"))})
    outcome, executor = execute(estd, simulated("baxter", scene=box_scene()), memory={LOCATED_ALONG: False})
    assert not outcome.succeeded and outcome.end_state == "failed", outcome.summary
    assert any("cannot tell where the object is in the hand" in reason for reason in last_reasons(executor))
