"""Issue 12: a sub-task's <object> that the run would leave out of the world is warned about."""

from __future__ import annotations

import shutil
from pathlib import Path

from atd.model import load_task

KNOWN_BOX = Path(__file__).resolve().parents[2] / "tests" / "data" / "known_box"


def test_a_sub_task_object_other_than_the_top_task_s_is_warned_about_at_its_state(tmp_path: Path) -> None:
    shutil.copy(KNOWN_BOX / "empty_the_box.xml", tmp_path)
    (tmp_path / "pick_one.xml").write_text((KNOWN_BOX / "pick_one.xml").read_text().replace(
        "<weight>0.1</weight>", "<weight>0.3</weight>"))
    _, found = load_task(tmp_path / "empty_the_box.xml")
    assert [(d.code, d.severity.value, Path(d.loc.file).name, d.loc.line) for d in found] == [
        ("ATD217", "warning", "empty_the_box.xml", 23)]


def test_the_same_object_in_both_is_fine() -> None:
    _, found = load_task(KNOWN_BOX / "empty_the_box.xml")
    assert found == []
