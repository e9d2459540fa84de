"""A multi-finger grasp closes on a ball at half speed: the SDH2's pinch fingers, 22 mm wide,
meet a 50 mm ball standing 1.6-3.1 cm off their line with a finger's side edge, and at the
full closing speed that first touch kicked it out of the search's reach (generalisation seed
20011, 5 of the SDH2's 9 lost balls; docs/robust-grasp.md, "The SDH2's ball")."""

from __future__ import annotations

from pathlib import Path

from tests.primitives.conftest import campaign_trial, generalisation_at


def test_the_sdh2_lifts_a_ball_its_first_close_met_off_the_pinch_line(tmp_path: Path) -> None:
    """Seed 77003, the ball at (0.22, 0.06) (centre_far), trial 2 with the approach error: at full speed the
    grasp ended "nothing between the fingers after 5 corrections"."""
    record = campaign_trial(generalisation_at(77003, tmp_path), 2, "robot=tombatossals", "arm=left", "engine=mujoco",
                            "perturbation=approach", "task=centre_far", "object=ball")
    assert record.judged_succeeded, (record.judge_reason, record.summary)
    assert record.task_succeeded, record.summary
