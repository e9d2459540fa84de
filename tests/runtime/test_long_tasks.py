"""Issue 12: a tick costs the same in a task of 3,000 states as in one of 300, and the
summary of a long run stays short while the trace keeps every record."""

from __future__ import annotations

import json
import time
import subprocess
import sys
from pathlib import Path

from atd.model.estd import Condition, Estd, EstdEvent, EstdState, EstdTransition
from atd.model.vocabulary import EventType, StateType
from atd.runtime.executor import Machine
from atd.runtime.trace import Trace
from atd.sim import make_robot
from atd.sim.scene import box_scene
from factories.registry import create
from primitives.base import Context


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


def idle_chain(states: int, period: float) -> Estd:
    """States with no controllers, each left on a one-tick timeout: the executor's own cost
    per state entered and per tick, with as little else as possible around it."""
    names = [f"s{i}" for i in range(states)] + ["done"]
    return Estd(
        robot="melfa", arm="main", initial="s0",
        states=tuple(EstdState(name=n, type=StateType.SUCCESS if n == "done" else StateType.MOVE, atd=n) for n in names),
        transitions=tuple(
            EstdTransition(origin=a, destination=b, atd=f"{a}->{b}",
                           events=(EstdEvent(type=EventType.TIMEOUT, atd=f"{a}->{b}/timeout",
                                             condition=Condition(kind="timeout", params={"seconds": period / 2})),))
            for a, b in zip(names, names[1:])),
    )


def seconds_per_state_entered(states: int) -> float:
    """What entering a state costs the executor in a machine of `states` states, the best of
    nine rounds of 500 entries (a loaded machine's pauses fall in some rounds, not all) spread over the machine (entering is part of the tick that
    takes a transition)."""
    robot = make_robot(create("melfa").robot, box_scene())
    try:
        machine = Machine(idle_chain(states, robot.info.control_period), "", Context(info=robot.info, params={}),
                          Trace(), [])
        readings = robot.read()
        names = [f"s{i}" for i in range(0, states, states // 500)]
        best = float("inf")
        for _ in range(9):
            started = time.perf_counter()
            for name in names:
                machine.enter(name, readings)
            best = min(best, (time.perf_counter() - started) / len(names))
    finally:
        robot.close()
    return best


def test_a_state_costs_the_same_to_enter_in_a_big_machine() -> None:
    small = seconds_per_state_entered(500)
    big = seconds_per_state_entered(10_000)
    assert big < 3 * small, (small, big)  # measured: 1.3x now, 14.7x when entering scanned every transition


def test_a_long_run_summary_is_capped_and_the_trace_is_whole(tmp_path: Path) -> None:
    trace = tmp_path / "run.jsonl"
    out = run(tmp_path, 600, "--trace", str(trace))
    assert len(out.splitlines()) < 100
    assert "... 561 more states visited" in out and "... 560 more events" in out
    records = [json.loads(line) for line in trace.read_text().splitlines()]
    assert sum(r["type"] == "enter" for r in records) == 601
