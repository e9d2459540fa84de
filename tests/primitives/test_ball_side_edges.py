"""The SDH2 does not move across a ball its pads press near their side edges: moved only to
the edge contacts, short of the ball's centre, it closed on the same flank again and again,
each squeeze and reopening rolling the ball on, until a close kicked it away; the weighing
says where the ball's weight hangs instead (docs/robust-grasp.md, "A ball pinched at the
pads' edges")."""

from __future__ import annotations

from pathlib import Path

from tests.primitives.conftest import campaign_trial, generalisation_at


def test_the_sdh2_lifts_a_ball_its_pads_pressed_near_their_side_edges(tmp_path: Path) -> None:
    """Seed 89856, the ball at (0.22, 0.06) (centre_far), trial 4 with the approach error: the
    first close pressed it with both pads' outermost rows alone, 9 mm across the pinch line
    (their centres of pressure); moved across that far close after close, the grasp ended "nothing
    between the fingers after 5 corrections", the ball 14 cm from where it stood. Now that
    first pinch is weighed (2.0 cm off the line, carried by friction) and lifted."""
    record = campaign_trial(generalisation_at(89856, tmp_path), 4, "robot=tombatossals", "arm=left", "engine=mujoco",
                            "perturbation=approach", "task=centre_far", "object=ball")
    assert record.judged_succeeded, (record.judge_reason, record.summary)
    assert record.task_succeeded, record.summary
