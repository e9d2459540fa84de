"""Issue 12: validation and its hints cost time in proportion to the task's size.

Timed as ratios between two sizes measured in the same test, so a busy machine slows both:
eight times the size must cost well under the 64 times a quadratic check would.
"""

from __future__ import annotations

import time
from pathlib import Path

from atd.model import load_task
from benchmarks.bench_validate import chain


def seconds_to_load(tmp_path: Path, text: str) -> tuple[float, list]:
    """The best of three loads: one slowed by another process would fake a quadratic cost."""
    path = tmp_path / f"t{len(text)}.xml"
    path.write_text(text)
    times = []
    for _ in range(3):
        started = time.perf_counter()
        _, found = load_task(path)
        times.append(time.perf_counter() - started)
    return min(times), found


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
