"""Time `atd validate` on a generated task of 10,000 states and 30,000 transitions.

Prints the time to parse + check the big task, against a baseline measured in the same
run: lxml merely parsing the same bytes (the floor any validator pays). Target: < 2 s.

    python benchmarks/bench_validate.py
"""

from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

from lxml import etree

from atd.model import load_task

STATES = 10_000
TRANSITIONS = 30_000


def generate(states: int = STATES, transitions: int = TRANSITIONS) -> bytes:
    """A chain of primitives, each with a success edge, a timeout back and a failure edge."""
    kinds = ["move", "grasp", "transport", "place", "release"]
    lines = ["<statemachine>",
             "  <object><pose>1 0 0 0.1 0 1 0 0 0 0 1 0.025 0 0 0 1</pose><class>box</class></object>"]
    body = states - 2
    for i in range(body):
        kind = kinds[i % len(kinds)]
        path = "<path><position>0.1 0 0.15</position></path>" if kind in ("move", "transport", "place") else ""
        lines.append(f'  <state name="s{i}" type="{kind}"><movement>guarded</movement>{path}</state>')
    lines += ['  <state name="done" type="success"/>', '  <state name="failed" type="failure"/>']
    per_state = transitions // body
    for i in range(body):
        nxt = f"s{i + 1}" if i + 1 < body else "done"
        lines.append(f'  <transition origin="s{i}" destination="{nxt}"><success/></transition>')
        lines.append(f'  <transition origin="s{i}" destination="s{max(i - 1, 0)}"><timeout>5</timeout></transition>')
        lines.append(f'  <transition origin="s{i}" destination="failed"><error/></transition>')
    extra = transitions - per_state * body
    for i in range(extra):
        lines.append(f'  <transition origin="s{i}" destination="failed"><hardware_failure/></transition>')
    lines.append("</statemachine>")
    return "\n".join(lines).encode()


def best_of(runs: int, work) -> float:
    times = []
    for _ in range(runs):
        started = time.perf_counter()
        work()
        times.append(time.perf_counter() - started)
    return min(times)


def main() -> int:
    data = generate()
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "big.xml"
        path.write_bytes(data)
        task, found = load_task(path)
        assert task is not None and len(task.states) == STATES and len(task.transitions) == TRANSITIONS
        assert not found, found[:3]
        baseline = best_of(3, lambda: etree.fromstring(data))
        ours = best_of(3, lambda: load_task(path))
    print(f"task: {STATES} states, {TRANSITIONS} transitions, {len(data) / 1e6:.1f} MB")
    print(f"lxml parse only (baseline): {baseline:.3f} s")
    print(f"atd validate (parse + read + XSD + graph checks): {ours:.3f} s  ({ours / baseline:.1f}x baseline)")
    print(f"target < 2 s: {'met' if ours < 2 else 'MISSED'}")
    return 0 if ours < 2 else 1


if __name__ == "__main__":
    sys.exit(main())
