"""Issue 12: validation and its hints cost time in proportion to the task's size.

Timed as ratios between two sizes measured in the same test, so a busy machine slows both:
eight times the size must cost well under the 64 times a quadratic check would.
"""

from __future__ import annotations

import time
from pathlib import Path

from atd.model import load_task


def chain(states: int, misspelt: int = 0) -> str:
    """A chain of moves, each with its own failure end (one end state per move), the first
    `misspelt` transitions naming states that do not exist."""
    lines = ["<statemachine>"]
    for i in range(states):
        lines.append(f'<state name="s{i}" type="move"><path><position>0.1 0 0.15</position></path></state>')
        lines.append(f'<state name="f{i}" type="failure"/>')
    lines.append('<state name="done" type="success"/>')
    for i in range(states):
        nxt = f"s{i + 1}" if i + 1 < states else "done"
        lines.append(f'<transition origin="s{i}" destination="{f"z{i + 1}q" if i < misspelt else nxt}"><success/></transition>')
        lines.append(f'<transition origin="s{i}" destination="f{i}"><timeout>5</timeout></transition>')
    return "\n".join(lines + ["</statemachine>"])


def seconds_to_load(tmp_path: Path, text: str) -> tuple[float, list]:
    path = tmp_path / f"t{len(text)}.xml"
    path.write_text(text)
    started = time.perf_counter()
    _, found = load_task(path)
    return time.perf_counter() - started, found


def test_many_end_states_validate_in_linear_time(tmp_path: Path) -> None:
    small, found_small = seconds_to_load(tmp_path, chain(1_000))
    big, found_big = seconds_to_load(tmp_path, chain(8_000))
    assert found_small == [] and found_big == []
    assert big < 20 * small, (small, big)


def test_hints_for_many_misspelt_names_cost_linear_time(tmp_path: Path) -> None:
    small, found_small = seconds_to_load(tmp_path, chain(500, misspelt=250))
    big, found_big = seconds_to_load(tmp_path, chain(4_000, misspelt=2_000))
    assert sum(d.code == "ATD202" for d in found_big) == 2_000
    assert big < 20 * small, (small, big)
    hinted = [d for d in found_big if d.code == "ATD202" and d.hint and d.hint.startswith("did you mean")]
    assert len(hinted) > 1_800
    assert next(d.hint for d in hinted if "'z1000q'" in d.message) == "did you mean 's1000'?"
