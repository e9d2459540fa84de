"""`atd campaign report` and `atd campaign export` as a user meets them: exit codes and
one-line errors, never a traceback."""

from __future__ import annotations

import csv
import io
import json
from pathlib import Path

from click.testing import CliRunner

from atd.cli import main


def _atd(*args: str) -> tuple[int, str, str]:
    result = CliRunner().invoke(main, ["campaign", *args])
    return result.exit_code, result.stdout, result.stderr


def test_report_prints_the_table_and_writes_the_plot(preset_store: Path, tmp_path: Path) -> None:
    plot = tmp_path / "campaign.png"
    code, out, err = _atd("report", str(preset_store), "--plot", str(plot))
    assert code == 0, err
    assert "thesis Table 3.3" in out and "naive + error" in out
    assert plot.read_bytes().startswith(b"\x89PNG")


def test_report_csv_to_a_file_has_a_row_per_group(preset_store: Path, tmp_path: Path) -> None:
    out_file = tmp_path / "report.csv"
    code, out, err = _atd("report", str(preset_store), "--format", "csv", "--by", "grasp,perturbation",
                          "-o", str(out_file))
    assert code == 0, err
    assert out == ""
    rows = list(csv.DictReader(io.StringIO(out_file.read_text())))
    assert [(r["grasp"], r["perturbation"], r["n"], r["successes"]) for r in rows] == [
        ("naive", "approach", "8", "2"), ("naive", "none", "8", "6"),
        ("robust", "approach", "8", "4"), ("robust", "none", "8", "8")]


def test_export_writes_every_trial(preset_store: Path, tmp_path: Path) -> None:
    out_file = tmp_path / "trials.json"
    code, _, err = _atd("export", str(preset_store), "--format", "json", "-o", str(out_file))
    assert code == 0, err
    assert len(json.loads(out_file.read_text())) == 32


def test_a_missing_store_is_one_line_and_exit_1(tmp_path: Path) -> None:
    missing = tmp_path / "nowhere.sqlite"
    for command in (["report", str(missing)], ["export", str(missing), "--format", "csv", "-o",
                                                str(tmp_path / "x.csv")]):
        code, out, err = _atd(*command)
        assert code == 1
        assert err == f"error: {missing}: no such file; give the --store file a campaign wrote\n"
    assert not (tmp_path / "x.csv").exists()


def test_a_file_that_is_no_store_is_one_line_and_exit_1(tmp_path: Path) -> None:
    task = tmp_path / "task.xml"
    task.write_text("<statemachine/>\n")
    code, _, err = _atd("report", str(task))
    assert code == 1
    assert err == f"error: {task} is not a campaign store (file is not a database); give the --store file a campaign wrote\n"


def test_usage_errors_name_the_fix(preset_store: Path, tmp_path: Path) -> None:
    code, _, err = _atd("report", str(preset_store), "--by", "gripper")
    assert code == 2 and "'gripper' is not a dimension; choose from task, robot" in err
    code, _, err = _atd("report", str(preset_store), "--plot", str(tmp_path / "plot.pdf"))
    assert code == 2 and "--plot must end in .png or .svg" in err
    code, _, err = _atd("report", str(preset_store), "-o", str(tmp_path / "missing" / "r.txt"))
    assert code == 2 and "does not exist" in err
    assert "Traceback" not in err
