"""A pinch that meets a ball with one pad, off its line, looks for it across the line on the
side that pad felt it, not along the line towards that finger (D5's finger-lost shift): a
ball between the fingers meets both, so one met only by one stood beside the line and the
touch rolled it on that way (docs/robust-grasp.md, "A ball met by one pad")."""

from __future__ import annotations

from pathlib import Path

from tests.primitives.conftest import campaign_trial, generalisation_at


def test_the_sdh2_lifts_a_ball_its_first_close_met_with_one_pad(tmp_path: Path) -> None:
    """Seed 40055, the ball at (0.02, 0.14) (left_near), trial 4 with the approach error: the
    first close met the ball 2.9 cm across the pinch line with finger 2's pad alone (its
    pressure 9 mm off the line); shifted 15 mm along the line, then searching from there, the
    grasp ended "nothing between the fingers after 5 corrections"."""
    record = campaign_trial(generalisation_at(40055, tmp_path), 4, "robot=tombatossals", "arm=left", "engine=mujoco",
                            "perturbation=approach", "task=left_near", "object=ball")
    assert record.judged_succeeded, (record.judge_reason, record.summary)
    assert record.task_succeeded, record.summary
