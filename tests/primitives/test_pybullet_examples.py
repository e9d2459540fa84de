"""The seeds' tasks in PyBullet, for the robots and arms whose MuJoCo runs are tested elsewhere:
the same primitives and conditions, the other engine's contacts. (Tombatossals' Barrett in
PyBullet: test_pybullet_three_finger.py.) The three-finger hands push with a finger pointing down:
their fists' sloping links wedged the box in PyBullet."""

from __future__ import annotations

import numpy as np
import pytest

from tests.primitives.conftest import EXAMPLES, run_example

CASES = [
    ("pick_and_place", "melfa", None), ("grasp_and_lift", "melfa", None), ("push_object", "melfa", None),
    ("pick_and_place", "baxter", None), ("grasp_and_lift", "baxter", None), ("push_object", "baxter", None),
    ("pick_and_place", "tombatossals", "left"),
    ("push_object", "tombatossals", "right"), ("push_object", "tombatossals", "left"),
]


@pytest.mark.parametrize("task, robot, arm", CASES, ids=lambda v: str(v))
def test_the_task_succeeds_in_pybullet_and_moves_the_object_as_asked(task: str, robot: str, arm: str | None) -> None:
    outcome, _, sim = run_example(EXAMPLES / f"{task}.xml", robot=robot, arm=arm, engine="pybullet")
    try:
        assert outcome.succeeded, outcome.summary
        where = sim.object_pose()[:3, 3]
    finally:
        sim.close()
    if task == "pick_and_place":
        assert np.linalg.norm(where[:2] - (0.10, 0.10)) < 0.02, f"the box ended at {where}"
    elif task == "grasp_and_lift":
        assert where[2] - 0.04 >= 0.08, f"the cylinder was lifted only to z = {where[2]:.3f}"
    else:  # the path ends at y = 0.01: the box's centre half its width (2.5 cm) on, give or take the pushing face
        assert 0.03 <= where[1] <= 0.07, f"the box was pushed to y = {where[1]:.3f}"
        assert abs(where[0] - 0.10) < 0.01 and abs(where[2] - 0.025) < 0.002, f"the box strayed to {where}"
