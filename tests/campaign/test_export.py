"""`atd campaign export`: every trial, every field, sampled values as their own columns."""

from __future__ import annotations

import csv
import io
import json

from atd.campaign.export import export
from atd.campaign.record import TrialRecord
from tests.campaign.conftest import approach, trial


def test_json_export_reads_back_to_the_same_trials() -> None:
    records = [trial(0, perturbation="approach", sampled=approach(0.03, 9.0)), trial(1, status="error")]
    back = [TrialRecord.from_dict(row) for row in json.loads(export(records, "json"))]
    assert back == records


def test_csv_export_has_a_row_per_trial_and_a_column_per_sampled_value() -> None:
    records = [trial(0, perturbation="approach", sampled=approach(0.03, 9.0)), trial(0, grasp="robust")]
    rows = list(csv.DictReader(io.StringIO(export(records, "csv"))))
    assert len(rows) == 2
    first, second = rows
    assert first["perturbation"] == "approach" and first["sampled.translation"] == "0.03"
    assert first["sampled.yaw"] == "9.0" and first["measurements.lift"] == "0.08"
    assert second["sampled.translation"] == ""  # no approach error was drawn for it
    assert json.loads(first["events"])[0]["event"] == "grasp_stable"
    assert list(first)[:9] == ["task", "robot", "arm", "engine", "grasp", "object", "perturbation", "index", "seed"]
    assert {"status", "error", "task_succeeded", "judged_succeeded", "judge_reason", "end_state", "summary",
            "sim_time", "wall_time", "setup_time"} <= set(first)


def test_an_empty_store_exports_a_header_and_no_rows() -> None:
    assert export([], "csv").splitlines()[0].startswith("task,robot,arm,engine,grasp,object,perturbation,index")
    assert json.loads(export([], "json")) == []
