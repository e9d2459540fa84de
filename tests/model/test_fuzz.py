"""Issue 12: a seeded mutation fuzzer over the examples and test data. Whatever the bytes,
reading, validating and translating give diagnostics, never an exception.

Mutations are what hostile or careless files hold: flipped and deleted bytes, truncation,
odd numbers (NaN, infinities, huge, negative, zero), markup and entity fragments, names
over 255 bytes, duplicated and dropped lines, other encodings.
"""

from __future__ import annotations

import random
import shutil
from pathlib import Path

from atd.model import Severity, load_task
from factories.registry import create
from tests.conftest import EXAMPLES, SEEDS
from translator import translate

SEED = 12
INPUTS = 3_000

TOKENS = [b"nan", b"-nan", b"inf", b"-inf", b"1e309", b"-1", b"0", b"1e-12", b"99999999", b"0x10", b"",
          b"<", b">", b"&", b"&amp;", b"&lt;", b"<!--", b"-->", b"<![CDATA[", b"]]>", b"\"", b"'", b"\x00",
          b"\xff\xfe", b"\xc3\x28", b"<state/>", b"<transition/>", b"<parameter name=\"max_speed\">nan</parameter>",
          b"<timeout>nan</timeout>", b"<object><shape>m.stl</shape></object>", b"file=\"" + b"a" * 300 + b".xml\"",
          b"type=\"task\" file=\"empty_the_box.xml\"", b"<?xml version=\"1.0\" encoding=\"UTF-16\"?>"]


def mutate(data: bytes, rng: random.Random) -> bytes:
    """One to four random edits of a valid file."""
    for _ in range(rng.randint(1, 4)):
        at = rng.randrange(len(data) + 1)
        kind = rng.randrange(7)
        if kind == 0:  # flip a byte
            if data:
                at = min(at, len(data) - 1)
                data = data[:at] + bytes([rng.randrange(256)]) + data[at + 1:]
        elif kind == 1:  # delete a run
            data = data[:at] + data[at + rng.randint(1, 40):]
        elif kind == 2:  # insert a token
            data = data[:at] + rng.choice(TOKENS) + data[at:]
        elif kind == 3:  # replace a number-like word by a token
            words = data.split(b" ")
            i = rng.randrange(len(words))
            words[i] = rng.choice(TOKENS)
            data = b" ".join(words)
        elif kind == 4:  # truncate
            data = data[:at]
        elif kind == 5:  # duplicate or drop a line
            lines = data.split(b"\n")
            i = rng.randrange(len(lines))
            lines.insert(i, lines[i]) if rng.random() < 0.5 else lines.pop(i)
            data = b"\n".join(lines)
        else:  # another encoding
            data = data.decode("utf-8", errors="replace").encode(rng.choice(["utf-16", "utf-16-be", "latin-1"]),
                                                                  errors="replace")
    return data


def test_mutated_tasks_give_diagnostics_never_an_exception(tmp_path: Path) -> None:
    for source in [*EXAMPLES.glob("*.xml"), *SEEDS.glob("*.xml")]:
        shutil.copy(source, tmp_path)
    originals = sorted(p.read_bytes() for p in tmp_path.glob("*.xml"))
    rng = random.Random(SEED)
    melfa = create("melfa")
    outcomes = {"invalid": 0, "translated": 0, "refused": 0}
    for i in range(INPUTS):
        path = tmp_path / f"mutant{i % 50}.xml"
        path.write_bytes(mutate(rng.choice(originals), rng))
        try:
            task, found = load_task(path)
            if task is None or any(d.severity is Severity.ERROR for d in found):
                assert any(d.severity is Severity.ERROR for d in found)
                outcomes["invalid"] += 1
                continue
            result = translate(task, melfa)
            outcomes["translated" if result.ok else "refused"] += 1
            assert result.ok or result.diagnostics
        except Exception as exc:
            raise AssertionError(f"input {i} (seed {SEED}) raised {exc!r}; its bytes are in {path}") from exc
    assert min(outcomes.values()) > 0, outcomes  # the fuzzer reaches every outcome, not only the parser
