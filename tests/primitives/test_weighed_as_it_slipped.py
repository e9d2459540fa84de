"""A weighing that feels the object slip out of the pads does not say it is held. At fresh
seed 49392 (MuJoCo, the Barrett, the seeds' approach error, centre_far, trial 1) the first
close held the tape; as the arm raised it to weigh it the tape slipped out of the pads, the
wrist felt less than half its weight, which reads as centred, and the grasp said "object
held" with both pads at 0 N: the state then waited until its time ran out (500d8f6). The
weighing waits for the pads, finds the tape dropped, grasps it again and the lift carries
it (docs/robust-grasp.md, "Weighed as it slipped out")."""

from __future__ import annotations

from pathlib import Path

from tests.primitives.conftest import campaign_trial, generalisation_at


def test_a_tape_that_slipped_out_as_it_was_weighed_is_grasped_again_and_lifted(tmp_path: Path) -> None:
    record = campaign_trial(generalisation_at(49392, tmp_path), 1, "robot=tombatossals", "arm=right", "engine=mujoco",
                            "perturbation=approach", "task=centre_far", "object=tape")
    assert record.judged_succeeded, (record.judge_reason, record.summary)
