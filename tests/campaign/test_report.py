"""What `atd campaign report` counts: the judge decides success, error trials stand apart,
and a Table 3.3-shaped campaign is shown beside the thesis."""

from __future__ import annotations

import csv
import io
import json

import pytest

from atd.campaign.formats import render
from atd.campaign.record import DIMENSIONS
from atd.campaign.report import ANY, build_report, group, parse_by
from tests.campaign.conftest import preset_records, trial

CSV_HEADER = ["task", "robot", "arm", "engine", "grasp", "object", "perturbation", "n", "successes", "rate",
              "low", "high", "false_successes"]


def test_the_judge_decides_success_and_disagreements_are_counted_both_ways() -> None:
    records = [
        trial(0, judged=True),
        trial(1, judged=False, task_said=True),  # the task said success; the object is on the table
        trial(2, judged=False, task_said=True),
        trial(3, judged=True, task_said=False),  # the task gave up; the object was held
        trial(4, status="error", judged=False),
    ]
    [cell] = group(records)
    assert (cell.n, cell.successes, cell.false_successes, cell.false_failures, cell.errors) == (4, 2, 2, 1, 1)
    assert cell.rate == 0.5


def test_grouping_by_some_dimensions_pools_the_others() -> None:
    records = preset_records()
    groups = group(records, ("grasp",))
    assert [(g.value("grasp"), g.value("object"), g.n, g.successes) for g in groups] == [
        ("naive", ANY, 16, 8), ("robust", ANY, 16, 12)]
    per_cell = group(records)
    assert len(per_cell) == 8 and all(g.n == 4 for g in per_cell)


def test_per_condition_pools_the_objects() -> None:
    report = build_report(preset_records())
    assert [(c.value("grasp"), c.value("perturbation"), c.value("object"), c.n, c.successes)
            for c in report.conditions] == [
        ("naive", "approach", ANY, 8, 2), ("naive", "none", ANY, 8, 6),
        ("robust", "approach", ANY, 8, 4), ("robust", "none", ANY, 8, 8)]


def test_csv_has_one_row_per_group_with_the_promised_columns_first() -> None:
    text = render(build_report(preset_records(), ("grasp", "perturbation")), "csv")
    rows = list(csv.reader(io.StringIO(text)))
    assert rows[0][:len(CSV_HEADER)] == CSV_HEADER
    assert len(rows) == 1 + 4
    naive_error = dict(zip(rows[0], rows[1]))
    assert naive_error["grasp"] == "naive" and naive_error["perturbation"] == "approach"
    assert naive_error["object"] == naive_error["robot"] == "*"
    assert (naive_error["n"], naive_error["successes"], float(naive_error["rate"])) == ("8", "2", 0.25)
    assert float(naive_error["low"]) == pytest.approx(0.0715, abs=1e-4)
    assert float(naive_error["high"]) == pytest.approx(0.5907, abs=1e-4)


def test_table_3_3_appears_beside_ours_for_a_campaign_of_its_shape() -> None:
    text = render(build_report(preset_records()), "table")
    assert "thesis Table 3.3" in text
    naive_error = next(line for line in text.splitlines() if "naive + error" in line)
    assert "19.0%" in naive_error and "25.0%" in naive_error  # the thesis's figure, then ours
    robust = next(line for line in text.splitlines() if " robust " in line and "99.0%" in line)
    assert "100.0%" in robust
    data = json.loads(render(build_report(preset_records()), "json"))
    assert [(r["row"], r["thesis"]["successes"], r["ours"]["successes"]) for r in data["table_3_3"]] == [
        ("naive", 88, 6), ("robust", 99, 8), ("naive + error", 19, 2), ("robust + error", 59, 4)]


def test_table_3_3_is_left_out_for_other_campaigns() -> None:
    records = [trial(i, perturbation="object_pose") for i in range(3)]
    report = build_report(records)
    assert report.thesis == []
    assert "Table 3.3" not in render(report, "table") and "Table 3.3" not in render(report, "markdown")


def test_markdown_is_a_table_per_section() -> None:
    text = render(build_report(preset_records()), "markdown")
    assert sum(line.startswith("| --- |") for line in text.splitlines()) == 3  # cells, conditions, Table 3.3
    assert "| grasp_and_lift | tombatossals | right | mujoco | naive + error | 19.0% |" in text


def test_by_names_dimensions_and_refuses_others() -> None:
    assert parse_by("grasp, object") == ("grasp", "object")
    with pytest.raises(ValueError, match="'gripper' is not a dimension; choose from task, robot"):
        parse_by("grasp,gripper")
    assert parse_by(",".join(DIMENSIONS)) == DIMENSIONS


def test_an_empty_store_says_so_and_its_csv_is_a_header() -> None:
    report = build_report([])
    assert render(report, "table") == "no trials stored yet\n"
    assert render(report, "csv").splitlines() == [",".join(CSV_HEADER) + ",false_failures,errors"]
