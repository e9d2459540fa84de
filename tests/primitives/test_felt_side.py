"""A close that found nothing between the fingers after one pad felt the object above the
table looks first on that side. At fresh seed 50255 (right_far, wood, trial 0) the Barrett's
approach stopped on its fingertips on the table beside the block; finger 2's pad felt it on
the first close from 2.8 cm one side of the pinch line to 1.2 cm the other, where it was
left, 4.8 cm off; the search stepped the other way first, and the grasp's 20 s ran out a
close short (docs/robust-grasp.md, "The Barrett's first search step, chosen by the pads")."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from primitives.hands.pinch_search import PinchSearch
from tests.primitives.conftest import campaign_trial, generalisation_at


def test_the_wood_felt_by_one_pad_is_looked_for_on_its_side_and_lifted(tmp_path: Path) -> None:
    record = campaign_trial(generalisation_at(50255, tmp_path), 0, "robot=tombatossals", "arm=right", "engine=mujoco",
                            "perturbation=approach", "task=right_far", "object=wood")
    assert record.judged_succeeded, (record.judge_reason, record.summary)


def test_the_search_steps_first_to_the_nearest_point_on_the_felt_side() -> None:
    search = PinchSearch(np.array([0.0, 1.0]), 0.025, 0.01, 0.01)
    assert np.allclose(search.next(side=-1.0), [0.0, -0.025, 0.0])
    assert np.allclose(search.next(side=-1.0), [0.0, -0.025, 0.0])  # on to -5 cm, the one point left that way
    assert np.allclose(search.next(), [0.0, 0.075, 0.0])  # no side felt: the fixed order, +2.5 cm
