"""A pinch that drops its object while the arm lifts it to weigh it closes next at the
height it closed before: the Barrett's pinch never follows the table down
(`rising_grasps`), and its closes after such a drop ran WEIGH_LIFT (15 mm) higher, their
fingertips passing over a ball's top (docs/robust-grasp.md, "A ball dropped while weighed")."""

from __future__ import annotations

from tests.primitives.conftest import preset_trials


def test_the_barrett_grasps_a_ball_again_at_its_height_after_it_slipped_out_in_the_weighing() -> None:
    """The Table 3.3 preset's Barrett ball, PyBullet, trial 0 with the approach error: the ball
    slipped out as the weighing lifted it, the next two closes (0.8 and 1.6 cm across the ball's
    centre) passed over it and the grasp timed out."""
    [record] = preset_trials((0,), robot="tombatossals", arm="right", engine="pybullet", grasp="robust",
                             object="ball", perturbation="approach")
    assert record.judged_succeeded, (record.judge_reason, record.summary)
    assert record.task_succeeded, record.summary
