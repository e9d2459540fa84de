"""A pinch whose weight hangs off its line says held only where friction has been seen to
hold it: the SDH2 held a mug 0.7 cm off its pinch line at its strongest squeeze (pads 2.5
and 2.2 N), the weight turning it harder than friction carries, and a duck 3.4 cm off at
the grasp force, further off than any hold seen to last; each lift said success and the
object turned out of the fingers in the judge's hold (generalisation.toml at base seed
71389, left_near, trial 0: false successes at a7a8317, the duck's still at 01264cb).
OFF_CENTRE, the distance a weight may hang off the line, was measured at the grasp force."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.primitives.conftest import campaign_trial, generalisation_at


@pytest.mark.parametrize("obj", ["mug", "duck"])
def test_the_sdh2s_pinch_with_its_weight_off_its_line_is_no_false_success(tmp_path: Path, obj: str) -> None:
    record = campaign_trial(generalisation_at(71389, tmp_path), 0, "task=left_near", "robot=tombatossals", "arm=left",
                            "engine=mujoco", f"object={obj}", "perturbation=approach")
    assert record.judged_succeeded or not record.task_succeeded, (record.judge_reason, record.summary)
