"""Pads that pinch the table hold nothing. At fresh seed 32856 (MuJoCo, the Barrett, the
seeds' approach error, right_far, trial 1) the approach stopped on the fingertips pressed on
the table (40 N) beside the stapler, 5.7 cm across the pinch line; the close pinched the
table at 20-24 N, pads 2 mm over it, and was held as a grasp that never settled: "pads never
settled at 5.0 N within 4 s" (an error, b7b2e70). Judged as the table, the hand rises off it,
closes again, searches and lifts the stapler (docs/robust-grasp.md, "Pads that pinch the table")."""

from __future__ import annotations

from pathlib import Path

from tests.primitives.conftest import campaign_trial, generalisation_at


def test_a_close_that_pinched_the_table_rises_finds_the_stapler_and_lifts_it(tmp_path: Path) -> None:
    record = campaign_trial(generalisation_at(32856, tmp_path), 1, "robot=tombatossals", "arm=right", "engine=mujoco",
                            "perturbation=approach", "task=right_far", "object=stapler")
    assert record.judged_succeeded, (record.judge_reason, record.summary)
