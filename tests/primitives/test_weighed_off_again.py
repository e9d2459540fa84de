"""A pinch weighed off its line again after a regrasp across to the weight is lifted: at
generalisation seed 24683 the Barrett pinched the bunny at centre_far, weighed it 1.9 cm off
the pinch line, set it down and closed again 1.9 cm across, and weighed it 1.6 cm off the
same side: its pads met the same part of the bunny wherever the hand moved, and the regrasps
went on until the grasp's 20 s ran out (docs/robust-grasp.md, "The Barrett's bunny weighed
off its line again")."""

from __future__ import annotations

from pathlib import Path

from tests.primitives.conftest import campaign_trial, generalisation_at


def test_a_bunny_weighed_off_its_pinch_line_again_is_lifted_not_regrasped_until_the_time_runs_out(
        tmp_path: Path) -> None:
    record = campaign_trial(generalisation_at(24683, tmp_path), 1, "robot=tombatossals", "arm=right", "engine=mujoco",
                            "perturbation=approach", "task=centre_far", "object=bunny")
    assert record.judged_succeeded, (record.judge_reason, record.summary)
    held = [why for event in record.events for why in event["why"] if why.startswith("object held after")]
    assert held and "off the pinch line" in held[0], record.events
