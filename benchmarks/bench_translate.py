"""Time `translate` on the generated 10,000-state / 30,000-transition ATD, for every robot.

Uses the same generated task as bench_validate.py. Prints, per robot, the best of 3
translation times (model in, ESTD model out) and the time to write the ESTD XML, and the
ratio of translating to reading and validating the same ATD, measured in the same run.
Target: translation < 3 s per robot. Then issue 12's near-linear cost: translating chains of
1,000 and 8,000 moves (each with its own failure end) for the Melfa, whose times should
stand about 8:1, far from the 64:1 of a quadratic cost.

    python benchmarks/bench_translate.py
"""

from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from atd.model import load_task  # noqa: E402
from atd.model.estd_xml import estd_to_xml  # noqa: E402
from benchmarks.bench_validate import STATES, TRANSITIONS, best_of, chain, generate  # noqa: E402
from factories.registry import create  # noqa: E402
from translator import translate  # noqa: E402

TARGET_SECONDS = 3.0


def main() -> int:
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "big.xml"
        path.write_bytes(generate())
        task, found = load_task(path)
        baseline = best_of(3, lambda: load_task(path))
    assert task is not None and len(task.states) == STATES and len(task.transitions) == TRANSITIONS
    print(f"translate a {STATES:,}-state / {TRANSITIONS:,}-transition ATD (best of 3)")
    print(f"  baseline: reading and validating it (load_task) {baseline:5.2f} s")
    worst = 0.0
    for robot in ("tombatossals", "melfa", "baxter"):
        factory = create(robot)
        result = None

        def run() -> None:
            nonlocal result
            result = translate(task, factory)

        seconds = best_of(3, run)
        assert result is not None and result.ok, [d.render() for d in result.diagnostics[:3]]
        started = time.perf_counter()
        size = len(estd_to_xml(result.estd))
        write = time.perf_counter() - started
        worst = max(worst, seconds)
        print(f"  {robot:13s} translate {seconds:5.2f} s ({seconds / baseline:.1f}x baseline)   "
              f"write XML {write:5.2f} s ({size / 1e6:.1f} MB)")
    print(f"slowest translation {worst:.2f} s, target < {TARGET_SECONDS:g} s: {'ok' if worst < TARGET_SECONDS else 'MISSED'}")
    ratio = scaling()
    return 0 if worst < TARGET_SECONDS and ratio < 16 else 1


def scaling() -> float:
    """Seconds to translate chains of 1,000 and 8,000 moves for the Melfa, and their ratio."""
    factory = create("melfa")
    seconds = {}
    with tempfile.TemporaryDirectory() as tmp:
        for moves in (1_000, 8_000):
            path = Path(tmp) / f"chain{moves}.xml"
            path.write_text(chain(moves))
            task, found = load_task(path)
            assert task is not None and not found, found[:3]
            seconds[moves] = best_of(3, lambda: translate(task, factory))
    ratio = seconds[8_000] / seconds[1_000]
    print(f"translate chains of 1,000 and 8,000 moves (melfa): {seconds[1_000]:.3f} s, {seconds[8_000]:.3f} s, "
          f"ratio {ratio:.1f} for 8x the size (linear: 8, quadratic: 64)")
    return ratio


if __name__ == "__main__":
    raise SystemExit(main())
