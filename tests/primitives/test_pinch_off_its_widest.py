"""A pinch narrower than its object by more than friction allows is no hold: at
generalisation seed 27191 the Barrett pinched the mug 40 mm apart across its 49 mm body,
its pads' corners on faces turned 34 degrees off the squeeze line, past the 31 degrees of
friction; weighed (0.5 cm off the line), lifted, it said success and slid out of the
fingertips 0.6 s into the judge's hold (docs/robust-grasp.md, "The mug squeezed out")."""

from __future__ import annotations

from pathlib import Path

from atd.campaign.cells import parse_only, plans
from atd.campaign.spec import load_spec
from atd.campaign.trial import run_trial
from tests.primitives.conftest import EXAMPLES

CAMPAIGNS = EXAMPLES / "campaigns"


def test_the_barretts_mug_pinched_off_its_widest_is_no_false_success(tmp_path: Path) -> None:
    spec = (CAMPAIGNS / "generalisation.toml").read_text()
    spec = spec.replace("base_seed = 8117", "base_seed = 27191").replace('"places/', f'"{CAMPAIGNS}/places/')
    (tmp_path / "g.toml").write_text(spec)
    loaded, diagnostics = load_spec(tmp_path / "g.toml")
    assert loaded is not None, diagnostics
    only = parse_only(("task=centre_far", "robot=tombatossals", "arm=right", "engine=mujoco", "object=mug",
                       "perturbation=approach"))
    [record] = [run_trial(plan) for plan in plans(loaded, only, 2) if plan.index == 1]
    assert record.judged_succeeded or not record.task_succeeded, (record.judge_reason, record.summary)
