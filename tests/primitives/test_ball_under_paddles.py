"""The Baxter's paddles meet a ball on its flank as they come down over it: the descent passes
the ball's upper half slowly, so the touch does not send it rolling out of reach, and the wrist's
contact places the ball's centre by the sphere's geometry, inside the finger that met it or
beyond it (docs/robust-grasp.md, "The ball kicked by the paddles' descent")."""

from __future__ import annotations

from pathlib import Path

import pytest

from primitives.arm.jaw_ball import BallUnderJaws
from tests.primitives.conftest import campaign_trial, generalisation_at


def test_a_finger_pushed_outwards_has_the_ball_inside_it_and_one_pushed_inwards_beyond_it() -> None:
    ball = BallUnderJaws(centre_z=0.025, radius=0.025, reach_across=0.05)
    tips = 0.025 + 0.015  # the fingertips 15 mm over the ball's centre: its flank 20 mm from its edge
    assert ball.centre_across(lever=0.04, push=2.0, tips_z=tips) == pytest.approx(0.03)
    assert ball.centre_across(lever=0.04, push=-2.0, tips_z=tips) == pytest.approx(0.07)
    assert ball.centre_across(lever=-0.04, push=2.0, tips_z=tips) == pytest.approx(-0.07)
    assert ball.passing(0.05) and ball.passing(0.03) and not ball.passing(0.02) and not ball.passing(0.07)


def test_the_baxter_lifts_a_ball_its_paddle_met_on_the_flank_in_pybullet(tmp_path: Path) -> None:
    """Seed 69894, the ball at (0.02, 0.14) (left_near), the right arm, trial 3 with the approach
    error: the first descent's paddle came down on the ball's flank 3.5 cm across the paddles at
    4 cm/s, pressed it at 42 N and kicked it 14 cm away; the grasp timed out searching along the
    paddles."""
    record = campaign_trial(generalisation_at(69894, tmp_path), 3, "robot=baxter", "arm=right", "engine=pybullet",
                            "perturbation=approach", "task=left_near", "object=ball")
    assert record.judged_succeeded, (record.judge_reason, record.summary)
    assert record.task_succeeded, record.summary
