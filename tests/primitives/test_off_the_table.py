"""A multi-finger grasp told to close on a ball with a fingertip pad on the table first rises as
far as its closing swings the fingertips down: closed there, the Barrett's fingertips levered the
hand up only as fast as the arm gave way, 6-8 s of the grasp's 20 s for its first close, and
the searches that followed ran out of time (generalisation seed 53719, the Barrett's ball;
docs/robust-grasp.md, "The Barrett's first close levered up off the table")."""

from __future__ import annotations

from pathlib import Path

from tests.primitives.conftest import campaign_trial, generalisation_at


def test_the_barrett_rises_off_the_table_before_it_closes_and_lifts_the_ball_in_time(tmp_path: Path) -> None:
    """Seed 53719, the ball at right_far, trial 4 with the approach error: closing on the table
    the grasp timed out in its third close, the ball found."""
    record = campaign_trial(generalisation_at(53719, tmp_path), 4, "robot=tombatossals", "arm=right", "engine=mujoco",
                            "perturbation=approach", "task=right_far", "object=ball")
    assert record.judged_succeeded, (record.judge_reason, record.summary)
    assert record.task_succeeded, record.summary
