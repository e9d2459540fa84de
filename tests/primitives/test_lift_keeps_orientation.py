"""A transport lifts the object as the grasp holds it (issue 10): the Melfa, having grasped
with the tilt the seeds' approach error left, turned its hand level on the lift, met its
wrist singularity and stalled 10 cm short ("no progress for 2 s"), trial 3 of the preset's
Melfa/MuJoCo/ball cell with the approach error."""

from __future__ import annotations

from tests.primitives.conftest import preset_trials


def test_the_melfa_lifts_with_the_tilt_it_grasped_with() -> None:
    [record] = preset_trials((3,), robot="melfa", engine="mujoco", grasp="robust", object="ball",
                             perturbation="approach")
    assert record.judged_succeeded and record.task_succeeded, (record.judge_reason, record.summary)
