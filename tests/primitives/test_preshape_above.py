"""The Baxter's preshape, the guarded move into the robust jaw grasp, ends over the object's top:
the grasp's correction makes the descent onto it (4 cm/s, 8 N). Coming down to the object's centre
at 15 cm/s until the wrist felt 30 N, a paddle landed on a standing cylinder's top edge with the
approach error, swept it 6 cm and tipped it over, and it rolled off the table
(docs/robust-grasp.md, "A cylinder tipped by the Baxter's preshape")."""

from __future__ import annotations

from pathlib import Path

from tests.primitives.conftest import campaign_trial, generalisation_at


def test_the_baxter_lifts_a_cylinder_its_preshape_came_down_on(tmp_path: Path) -> None:
    """The shipped seed, the cylinder at (0.20, -0.12) (right_far), the right arm, trial 0 with the
    approach error: the preshape tipped the cylinder over and the grasp timed out, the cylinder
    rolled off the table."""
    record = campaign_trial(generalisation_at(8117, tmp_path), 0, "robot=baxter", "arm=right", "engine=mujoco",
                            "perturbation=approach", "task=right_far", "object=cylinder")
    assert record.judged_succeeded, (record.judge_reason, record.summary)
    assert record.task_succeeded, record.summary
