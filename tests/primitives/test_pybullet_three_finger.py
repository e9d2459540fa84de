"""Tombatossals' Barrett hand grasps through the executor in PyBullet as it does in MuJoCo:
the robust grasp has to find the object held (force adaptation settles on the pads) with
PyBullet's rigid contacts, not only with MuJoCo's soft ones."""

from __future__ import annotations

import numpy as np

from tests.primitives.conftest import EXAMPLES, run_example


def test_barrett_picks_and_places_the_box_in_pybullet() -> None:
    outcome, _, robot = run_example(EXAMPLES / "pick_and_place.xml", robot="tombatossals", arm="right",
                                    engine="pybullet")
    try:
        assert outcome.succeeded, outcome.summary
        box = robot.object_pose()[:3, 3]
    finally:
        robot.close()
    assert [v.atd for v in outcome.visits] == ["approach", "descend", "grasp", "lift", "carry", "put_down", "let_go",
                                               "retreat", "done"]
    assert np.linalg.norm(box - (0.10, 0.10, 0.025)) < 0.02, f"the box ended at {box}"


def test_barrett_grasps_and_lifts_the_cylinder_in_pybullet() -> None:
    outcome, _, robot = run_example(EXAMPLES / "grasp_and_lift.xml", robot="tombatossals", arm="right",
                                    engine="pybullet")
    try:
        assert outcome.succeeded, outcome.summary
        height = robot.object_pose()[2, 3]
    finally:
        robot.close()
    assert height - 0.04 >= 0.08, f"the cylinder was lifted only to z = {height:.3f}"  # it starts at z = 0.04
