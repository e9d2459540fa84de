"""A pinch that may creep out is watched before a lift says it holds: at generalisation
seed 27191 the Barrett pinched the mug 40 mm apart across its 49 mm body, its pads' corners
on faces turned past the friction angle; lifted, with its weight felt, its pads and fingers
steady, the lift said success, and the mug slid out of the fingertips 0.6 s into the
judge's hold; the shipped spec's seed had the same mug at trial 0 (docs/robust-grasp.md, "A
steep pinch watched"). In Table 3.3 it held the duck by its flank, its weight 1.3 cm off the
pinch line beyond the pads' 1.2 cm half-width, and the duck went the same way ("A pinch held
by the flank")."""

from __future__ import annotations

from pathlib import Path

from tests.primitives.conftest import CAMPAIGNS, campaign_trial


def test_a_lift_whose_mug_creeps_out_of_a_steep_pinch_says_it_lost_it() -> None:
    _says_it_lost_it(CAMPAIGNS / "generalisation.toml", 0, ("task=centre_far", "object=mug"), "the creeping pinch")


def test_a_lift_whose_duck_creeps_out_of_a_flank_pinch_says_it_lost_it() -> None:
    _says_it_lost_it(CAMPAIGNS / "table_3_3.toml", 1, ("grasp=robust", "object=duck"), "the flank pinch")


def _says_it_lost_it(spec: Path, trial: int, cell: tuple[str, ...], shows: str) -> None:
    """That trial of the Barrett's MuJoCo cell with the approach error ends in the lift on grasp_lost."""
    record = campaign_trial(spec, trial, "robot=tombatossals", "arm=right", "engine=mujoco", "perturbation=approach",
                            *cell)
    assert not record.judged_succeeded, f"the trial no longer shows {shows}"
    assert not record.task_succeeded, (record.judge_reason, record.summary)
    assert "grasp_lost" in record.summary, record.summary
