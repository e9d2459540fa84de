"""Untrusted files: each is refused with one clear diagnostic, quickly, leaking nothing."""

import time

import pytest

from atd.model import Severity, load_task
from atd.model.xmlsafe import MAX_BYTES

SECRET = "s3cr3t-token-that-must-not-leak"

BILLION_LAUGHS = """<?xml version="1.0"?>
<!DOCTYPE lolz [
 <!ENTITY lol "lol">
 <!ENTITY lol1 "&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;">
 <!ENTITY lol2 "&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;">
 <!ENTITY lol3 "&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;">
 <!ENTITY lol4 "&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;">
 <!ENTITY lol5 "&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;">
 <!ENTITY lol6 "&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;">
 <!ENTITY lol7 "&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;">
 <!ENTITY lol8 "&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;">
 <!ENTITY lol9 "&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;">
]>
<statemachine><state name="&lol9;" type="success"/></statemachine>
"""


def xxe(secret_path) -> str:
    return f"""<?xml version="1.0"?>
<!DOCTYPE statemachine [<!ENTITY leak SYSTEM "file://{secret_path}">]>
<statemachine><state name="&leak;" type="success"/></statemachine>
"""


def hostile_files(tmp_path):
    secret = tmp_path / "secret.txt"
    secret.write_text(SECRET)
    files = {
        "billion_laughs": (BILLION_LAUGHS.encode(), "ATD004", 2),
        "xxe": (xxe(secret).encode(), "ATD004", 2),
        "deep": (b"<statemachine>" + b"<a>" * 10_000 + b"</a>" * 10_000 + b"</statemachine>", "ATD005", 1),
        "truncated": (b'<statemachine>\n  <state name="a" type="move">\n    <movement>fr', "ATD003", 3),
        "binary": (bytes(range(256)) * 64, "ATD006", 1),
        "empty": (b"", "ATD006", 1),
    }
    for name, (data, code, line) in files.items():
        (tmp_path / f"{name}.xml").write_bytes(data)
    big = tmp_path / "big.xml"
    with big.open("wb") as out:  # 50 MB of otherwise harmless XML
        out.write(b"<statemachine>")
        out.write(b"<!--" + b"x" * (50 * 2**20) + b"-->")
        out.write(b"</statemachine>")
    files["big"] = (None, "ATD002", 1)
    return files


def test_hostile_files_each_give_one_error_fast(tmp_path):
    for name, (_, code, line) in hostile_files(tmp_path).items():
        started = time.perf_counter()
        task, found = load_task(tmp_path / f"{name}.xml")
        elapsed = time.perf_counter() - started
        assert task is None, name
        assert [(d.code, d.severity, d.loc.line) for d in found] == [(code, Severity.ERROR, line)], name
        assert elapsed < 1.0, f"{name} took {elapsed:.2f}s"
        assert SECRET not in found[0].render()


def test_big_file_is_refused_before_it_is_read(tmp_path):
    hostile_files(tmp_path)
    assert (tmp_path / "big.xml").stat().st_size > MAX_BYTES
    _, found = load_task(tmp_path / "big.xml")
    assert "larger than" in found[0].message


@pytest.mark.parametrize("name,code", [("nowhere.xml", "ATD001"), (".", "ATD001")])
def test_missing_or_wrong_path(tmp_path, name, code):
    task, found = load_task(tmp_path / name)
    assert task is None and [d.code for d in found] == [code]


def test_entities_are_never_expanded_into_the_model(tmp_path):
    """Even an entity the parser would accept stays unexpanded: the DOCTYPE is refused outright."""
    secret = tmp_path / "secret.txt"
    secret.write_text(SECRET)
    path = tmp_path / "xxe.xml"
    path.write_text(xxe(secret))
    task, found = load_task(path)
    assert task is None
    assert "DOCTYPE" in found[0].message and SECRET not in found[0].message
