"""Issue 12: a tick costs the same in a task of 3,000 states as in one of 300, and the
summary of a long run stays short while the trace keeps every record."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path
from types import FrameType
from typing import Callable

from atd.sim import make_robot
from atd.sim.scene import box_scene
from benchmarks.bench_state_entry import idle_machine, spread
from factories.registry import create


def chain(states: int) -> str:
    """Moves in a row, each left after a few ticks on a timeout: a run that enters a state every other tick."""
    lines = ["<statemachine>"]
    lines += [f'<state name="s{i}" type="move"><path><position>0.1 0 0.15</position></path></state>'
              for i in range(states)]
    lines.append('<state name="done" type="success"/>')
    lines += [f'<transition origin="s{i}" destination="{f"s{i + 1}" if i + 1 < states else "done"}">'
              f"<timeout>0.004</timeout></transition>" for i in range(states)]
    return "\n".join(lines + ["</statemachine>"])


def run(tmp_path: Path, states: int, *extra: str) -> str:
    task = tmp_path / f"chain{states}.xml"
    task.write_text(chain(states))
    done = subprocess.run([sys.executable, "-m", "atd", "run", str(task), "--robot", "melfa", "-q", *extra],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    return done.stdout


def lines_run_per_entry(states: int) -> float:
    """Python lines the executor runs (a loop's every pass counts) entering a state of an idle
    chain of `states` states, over 50 entries spread across the machine."""
    robot = make_robot(create("melfa").robot, box_scene())
    try:
        machine = idle_machine(states, robot)
        readings = robot.read()
        machine.enter("s0", readings)  # builds the machine's index of transitions, once
        names = spread(states, 50)
        count = 0

        def line(frame: FrameType, event: str, arg: object) -> Callable:
            nonlocal count
            count += event == "line"
            return line

        outer = sys.gettrace()
        sys.settrace(lambda frame, event, arg: line)
        try:
            for name in names:
                machine.enter(name, readings)
        finally:
            sys.settrace(outer)
    finally:
        robot.close()
    return count / len(names)


def test_a_state_costs_the_same_to_enter_in_a_big_machine() -> None:
    # counted, not timed (the timing is benchmarks/bench_state_entry.py): 235 lines an entry in
    # either; entering that scanned every transition ran 1,234 and 20,234
    assert lines_run_per_entry(10_000) == lines_run_per_entry(500)


def test_a_long_run_summary_is_capped_and_the_trace_is_whole(tmp_path: Path) -> None:
    trace = tmp_path / "run.jsonl"
    out = run(tmp_path, 600, "--trace", str(trace))
    assert len(out.splitlines()) < 100
    assert "... 561 more states visited" in out and "... 560 more events" in out
    records = [json.loads(line) for line in trace.read_text().splitlines()]
    assert sum(r["type"] == "enter" for r in records) == 601
