"""Issue 12: a tick costs the same in a task of 3,000 states as in one of 300, and the
summary of a long run stays short while the trace keeps every record."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

from atd.model.estd import Condition, Estd, EstdEvent, EstdState, EstdTransition
from atd.model.vocabulary import EventType, StateType
from atd.runtime.executor import Executor
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


def seconds_per_tick(states: int) -> float:
    robot = make_robot(create("melfa").robot, box_scene())
    try:
        outcome = Executor(idle_chain(states, robot.info.control_period), robot, Context(info=robot.info, params={})).run()
    finally:
        robot.close()
    assert outcome.succeeded and outcome.ticks >= states
    return outcome.wall_time / outcome.ticks


def test_tick_cost_does_not_grow_with_the_number_of_states() -> None:
    small = seconds_per_tick(500)
    big = seconds_per_tick(5_000)
    assert big < 1.7 * small, (small, big)  # measured: 1.13 now, 2.5 when entering a state scanned every transition


def test_a_long_run_summary_is_capped_and_the_trace_is_whole(tmp_path: Path) -> None:
    trace = tmp_path / "run.jsonl"
    out = run(tmp_path, 600, "--trace", str(trace))
    assert len(out.splitlines()) < 100
    assert "... 561 more states visited" in out and "... 560 more events" in out
    records = [json.loads(line) for line in trace.read_text().splitlines()]
    assert sum(r["type"] == "enter" for r in records) == 601
