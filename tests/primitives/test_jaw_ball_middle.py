"""Parallel jaws that meet a ball's flank above its middle go on down before they close: at
generalisation seed 8117 a Baxter paddle's edge met the ball 3.5 cm above its centre, the
jaws closed there on its cap, pressed it into the table and crept shut, and the grasp
waited out its 20 s for a grip that never held (docs/robust-grasp.md, "A ball's cap")."""

from __future__ import annotations

from pathlib import Path

from atd.campaign.cells import parse_only, plans
from atd.campaign.spec import load_spec
from atd.campaign.trial import run_trial
from tests.primitives.conftest import EXAMPLES

CAMPAIGNS = EXAMPLES / "campaigns"


def test_jaws_that_meet_a_ball_above_its_middle_grip_its_sides(tmp_path: Path) -> None:
    spec = (CAMPAIGNS / "generalisation.toml").read_text().replace('"places/', f'"{CAMPAIGNS}/places/')
    (tmp_path / "g.toml").write_text(spec)
    loaded, diagnostics = load_spec(tmp_path / "g.toml")
    assert loaded is not None, diagnostics
    only = parse_only(("task=left_near", "robot=baxter", "arm=right", "engine=mujoco", "object=ball",
                       "perturbation=approach"))
    [record] = [run_trial(plan) for plan in plans(loaded, only, 5) if plan.index == 4]
    assert record.task_succeeded and record.judged_succeeded, (record.summary, record.judge_reason)
