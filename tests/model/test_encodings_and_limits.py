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


@pytest.mark.parametrize("codec", ["utf-16-le", "utf-16-be"])
@pytest.mark.parametrize("start", ["\n", "  ", "\r\n"])
def test_utf16_without_mark_or_declaration_may_begin_with_white_space(tmp_path: Path, codec: str, start: str) -> None:
    body = EXAMPLE.read_text(encoding="utf-8").split("?>", 1)[1].lstrip()
    copy = tmp_path / EXAMPLE.name
    copy.write_bytes((start + body).encode(codec))
    task, found = load_task(copy)
    assert found == [] and task == load_task(EXAMPLE)[0]


@pytest.mark.parametrize("codec", ["utf-32", "utf-32-be"])
def test_utf32_is_named_not_called_binary(codec: str) -> None:
    data = EXAMPLE.read_bytes().decode("utf-8").encode(codec)
    _, found = parse_bytes(data if codec == "utf-32" else b"\x00\x00\xfe\xff" + data, "t.xml")
    assert [(d.code, "UTF-32" in d.message, d.hint) for d in found] == [("ATD006", True, "save the file as UTF-8")]


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
