"""The Melfa's jaws that grip the steel weight by its flank, beyond their pads' edge, do not lift
it there: at generalisation seed 79561 (PyBullet, left_near, trial 0) the approach error left
the jaws 2.1 cm off the weight's axis along their width, both pads felt it in their outer column
with 14.4 N, the grasp said held, and the weight slid out of the grip in the lift's first 0.1 s
(`grasp_lost`). A grip on the flank now reopens for the arm to move along the jaws
(docs/robust-grasp.md, "The steel weight held by its flank")."""

from __future__ import annotations

from pathlib import Path

from tests.primitives.conftest import campaign_trial, generalisation_at


def test_a_weight_gripped_by_its_flank_is_gripped_again_along_the_jaws_and_lifted(tmp_path: Path) -> None:
    record = campaign_trial(generalisation_at(79561, tmp_path), 0, "robot=melfa", "engine=pybullet",
                            "perturbation=approach", "task=left_near", "object=weight")
    assert record.judged_succeeded, (record.judge_reason, record.summary)
    assert not any(event["event"] == "grasp_lost" for event in record.events), record.events
