"""Issue 12: a UTF-16 task is read like a UTF-8 one; libxml2's limits are explained in our words."""

from __future__ import annotations

from pathlib import Path

import pytest

from atd.model import load_task
from atd.model.xmlsafe import parse_bytes

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "simple_move.xml"


@pytest.mark.parametrize("codec", ["utf-16", "utf-16-le", "utf-16-be"])
def test_utf16_task_reads_as_the_same_task(tmp_path: Path, codec: str) -> None:
    text = EXAMPLE.read_text(encoding="utf-8")
    copy = tmp_path / EXAMPLE.name
    copy.write_bytes(text.replace('encoding="UTF-8"', 'encoding="UTF-16"').encode(codec))
    original, _ = load_task(EXAMPLE)
    task, found = load_task(copy)
    assert found == [] and task == original


def test_broken_utf16_is_an_undecodable_file() -> None:
    _, found = parse_bytes(b"\xff\xfe<\x00s\x00\x00\xd8", "t.xml")
    assert [d.code for d in found] == ["ATD006"]


@pytest.mark.parametrize("body", [
    "<!--" + "x" * 10_000_100 + "-->",
    "<state name='" + "x" * 10_000_100 + "'/>",
    "x" * 10_000_100,
])
def test_overlong_text_is_explained_without_libxml2_words(body: str) -> None:
    _, found = parse_bytes(f"<statemachine>{body}</statemachine>".encode(), "t.xml")
    assert [d.code for d in found] == ["ATD007"]
    assert "10,000,000 characters" in found[0].message and "XML_PARSE_HUGE" not in found[0].render()


def test_overlong_element_name_is_explained() -> None:
    _, found = parse_bytes(f"<statemachine><{'x' * 60_000}/></statemachine>".encode(), "t.xml")
    assert [d.code for d in found] == ["ATD007"] and "name" in found[0].message
