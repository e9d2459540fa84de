"""Time validation on two generated tasks, each against a baseline measured in the same run.

- 10,000 states and 30,000 transitions, read and checked in this process, against lxml
  merely parsing the same bytes (the floor any validator pays). Target: < 2 s.
- Issue 12's 40,000-state chain (5.5 MB, one failure end per move) as a user runs it:
  `atd validate FILE` in a fresh process, against a fresh process that imports lxml and
  parses the file. Target: < 2 s.
- Issue 12's 2,000 misspelt state names (a chain of 4,000 moves whose first 2,000 success
  edges name no state), each with a "did you mean" hint: `atd validate FILE` in a fresh
  process. Target: < 2 s.

    python benchmarks/bench_validate.py
"""

from __future__ import annotations

import os
import subprocess
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


def chain(moves: int, misspelt: int = 0) -> str:
    """A chain of moves, each with its own failure end (one end state per move: 2 x `moves` + 1
    states), the first `misspelt` transitions naming states that do not exist."""
    lines = ["<statemachine>"]
    for i in range(moves):
        lines.append(f'<state name="s{i}" type="move"><path><position>0.1 0 0.15</position></path></state>')
        lines.append(f'<state name="f{i}" type="failure"/>')
    lines.append('<state name="done" type="success"/>')
    for i in range(moves):
        nxt = f"s{i + 1}" if i + 1 < moves else "done"
        lines.append(f'<transition origin="s{i}" destination="{f"z{i + 1}q" if i < misspelt else nxt}"><success/></transition>')
        lines.append(f'<transition origin="s{i}" destination="f{i}"><timeout>5</timeout></transition>')
    return "\n".join(lines + ["</statemachine>"])


def best_of(runs: int, work) -> float:
    times = []
    for _ in range(runs):
        started = time.perf_counter()
        work()
        times.append(time.perf_counter() - started)
    return min(times)


def fresh_processes(runs: int, *argv: str, exit_code: int = 0) -> tuple[float, float]:
    """The best wall and the best CPU seconds of `runs` fresh Pythons running `argv` (CPU time
    is what a busy machine inflates least)."""
    walls, cpus = [], []
    for _ in range(runs):
        before, started = os.times(), time.perf_counter()
        done = subprocess.run([sys.executable, *argv], capture_output=True)
        assert done.returncode == exit_code, done.stderr[-500:]
        walls.append(time.perf_counter() - started)
        after = os.times()
        cpus.append(after.children_user + after.children_system - before.children_user - before.children_system)
    return min(walls), min(cpus)


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
        ends = Path(tmp) / "chain.xml"
        ends.write_text(chain(20_000))
        megabytes = ends.stat().st_size / 1e6
        assert load_task(ends)[1] == []
        parse_only, parse_cpu = fresh_processes(
            3, "-c", "import sys; from lxml import etree; etree.parse(sys.argv[1])", str(ends))
        command, command_cpu = fresh_processes(3, "-m", "atd", "validate", str(ends))
        misspelt = Path(tmp) / "misspelt.xml"
        misspelt.write_text(chain(4_000, misspelt=2_000))
        hints, hints_cpu = fresh_processes(3, "-m", "atd", "validate", "--format", "json", str(misspelt), exit_code=1)
    print(f"task: {STATES} states, {TRANSITIONS} transitions, {len(data) / 1e6:.1f} MB")
    print(f"lxml parse only (baseline): {baseline:.3f} s")
    print(f"atd validate (parse + read + XSD + graph checks): {ours:.3f} s  ({ours / baseline:.1f}x baseline)")
    print(f"chain: {2 * 20_000 + 1} states, each move with its own failure end, {megabytes:.1f} MB")
    print(f"python + lxml parse, fresh process (baseline): {parse_only:.3f} s, CPU {parse_cpu:.3f} s")
    print(f"atd validate, fresh process: {command:.3f} s  ({command / parse_only:.1f}x baseline), "
          f"CPU {command_cpu:.3f} s  ({command_cpu / parse_cpu:.1f}x baseline)")
    print(f"2,000 misspelt names with hints, fresh process: {hints:.3f} s, CPU {hints_cpu:.3f} s")
    met = ours < 2 and command < 2 and hints < 2
    print(f"target < 2 s: {'met' if met else 'MISSED'}")
    return 0 if met else 1


if __name__ == "__main__":
    sys.exit(main())
