"""A pinch steeper than friction holds is watched before a lift says it holds: at
generalisation seed 27191 the Barrett pinched the mug 40 mm apart across its 49 mm body,
its pads' corners on faces turned past the friction angle; lifted, with its weight felt,
its pads and fingers steady, the lift said success, and the mug slid out of the
fingertips 0.6 s into the judge's hold (docs/robust-grasp.md, "A steep pinch watched")."""

from __future__ import annotations

from pathlib import Path

from atd.campaign.cells import parse_only, plans
from atd.campaign.spec import load_spec
from atd.campaign.trial import run_trial
from tests.primitives.conftest import EXAMPLES

CAMPAIGNS = EXAMPLES / "campaigns"


def test_a_lift_whose_mug_creeps_out_of_a_steep_pinch_says_it_lost_it(tmp_path: Path) -> None:
    spec = (CAMPAIGNS / "generalisation.toml").read_text()
    spec = spec.replace("base_seed = 8117", "base_seed = 27191").replace('"places/', f'"{CAMPAIGNS}/places/')
    (tmp_path / "g.toml").write_text(spec)
    loaded, diagnostics = load_spec(tmp_path / "g.toml")
    assert loaded is not None, diagnostics
    only = parse_only(("task=centre_far", "robot=tombatossals", "arm=right", "engine=mujoco", "object=mug",
                       "perturbation=approach"))
    [record] = [run_trial(plan) for plan in plans(loaded, only, 2) if plan.index == 1]
    assert not record.judged_succeeded, "the trial no longer shows the creeping pinch"
    assert not record.task_succeeded, (record.judge_reason, record.summary)
    assert "grasp_lost" in record.summary, record.summary
