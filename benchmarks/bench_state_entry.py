"""What entering a state costs the executor in a machine of 10,000 states against one of 500,
measured beside each other (issue 12: entering once scanned every transition, 14.7x).

Each round enters 500 states spread over each machine, the small one then the big one; the
best round of each counts. Entering is the part of a tick that grows with the machine if
anything does: the tick that takes a transition builds the new state's controllers and
conditions. Target: the big machine at most 3x the small (measured 1.3x). The same work is
asserted by count, not time, in tests/runtime/test_long_tasks.py.

    python benchmarks/bench_state_entry.py [--rounds 9] [--cpu]

`--cpu` times this thread's CPU time instead of wall time, which other jobs on the host do
not inflate.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from atd.model.estd import Condition, Estd, EstdEvent, EstdState, EstdTransition  # noqa: E402
from atd.model.vocabulary import EventType, StateType  # noqa: E402
from atd.runtime.executor import Machine  # noqa: E402
from atd.runtime.trace import Trace  # noqa: E402
from atd.sim import make_robot  # noqa: E402
from atd.sim.scene import box_scene  # noqa: E402
from factories.registry import create  # noqa: E402
from primitives.base import Context  # noqa: E402
from primitives.robot import Readings, Robot  # noqa: E402

SMALL, BIG = 500, 10_000
ENTRIES = 500  # states entered a round, spread over the machine
TARGET = 3.0  # the big machine over the small; the regression it guards was 14.7x


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


def idle_machine(states: int, robot: Robot) -> Machine:
    """The executor's machine for an idle chain of `states` states on `robot`."""
    return Machine(idle_chain(states, robot.info.control_period), "", Context(info=robot.info, params={}), Trace(), [])


def spread(states: int, entries: int = ENTRIES) -> list[str]:
    """`entries` state names spread evenly over a chain of `states`."""
    return [f"s{i}" for i in range(0, states, states // entries)]


def seconds_per_entry(machine: Machine, names: list[str], readings: Readings, clock) -> float:
    started = clock()
    for name in names:
        machine.enter(name, readings)
    return (clock() - started) / len(names)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=9, help="rounds of each; the best counts")
    parser.add_argument("--cpu", action="store_true", help="time this thread's CPU time, not wall time")
    args = parser.parse_args()
    clock = time.thread_time if args.cpu else time.perf_counter
    robot = make_robot(create("melfa").robot, box_scene())
    try:
        readings = robot.read()
        machines = {size: (idle_machine(size, robot), spread(size)) for size in (SMALL, BIG)}
        for machine, _ in machines.values():
            machine.enter("s0", readings)  # builds the machine's index of transitions, once
        best = {size: float("inf") for size in machines}
        for _ in range(args.rounds):
            for size, (machine, names) in machines.items():
                best[size] = min(best[size], seconds_per_entry(machine, names, readings, clock))
    finally:
        robot.close()
    ratio = best[BIG] / best[SMALL]
    print(f"entering a state ({'CPU' if args.cpu else 'wall'} time, best of {args.rounds} rounds of {ENTRIES}): "
          f"{SMALL:,} states {best[SMALL] * 1e6:.1f} us, {BIG:,} states {best[BIG] * 1e6:.1f} us")
    print(f"ratio, {BIG:,} states over {SMALL:,}: {ratio:.2f}x (target < {TARGET:g}x: {'ok' if ratio < TARGET else 'MISSED'})")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
