"""Where a control tick of `atd run examples/pick_and_place.xml` goes, layer by layer (MuJoCo).

For each robot (and arm), four loops run as many control ticks as the pick-and-place takes:
the engine alone (`bare`), the robot interface with a still arm (`interface`: a command,
`step()` and a `read()` each tick), the executor running a state with no controllers that
ends on a timeout (`empty executor`: the automaton, one condition, the arbitrator, the
interface), and the whole task (`atd run`), with the time its physics steps took and its
executor's own time (all but the robot interface: conditions, controllers, arbitrator, DLS;
the timers add about 2 microseconds a tick). Prints microseconds per tick and each one's
ratio to bare stepping, and the whole run's time over its physics' (`run/phys`, issue 34's
measure of the executor against the run's own physics, target at most 1.5). The empty
executor's ratio is the floor under issue 5's target of 1.30 for this design in CPython,
whatever the primitives cost; the task's own physics (contacts, a moving arm) already
costs more than bare stepping.

    python benchmarks/bench_tick.py [--repeat 3] [--robot melfa] [--cpu]

`--cpu` times everything in this thread's CPU time instead of wall time: on a machine that
other processes load, wall time counts the time they take the core away, CPU time does not.

Where the executor's time goes, function by function: `--profile N` runs the task once per
robot under cProfile (after a run that warms it up) and prints the N functions that spent
the most time of their own. cProfile's own cost per Python call inflates Python code
against numpy's and MuJoCo's C, so read it for the order, and this table for the ratios.

    python benchmarks/bench_tick.py --robot melfa --profile 30
"""

from __future__ import annotations

import argparse
import cProfile
import pstats
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from atd.model import Task, load_task  # noqa: E402
from atd.model.estd import Condition, Estd, EstdEvent, EstdState, EstdTransition  # noqa: E402
from atd.model.vocabulary import EventType, StateType  # noqa: E402
from atd.runtime.executor import Executor, Outcome  # noqa: E402
from atd.runtime.session import Run  # noqa: E402
from atd.sim import make_robot, variants  # noqa: E402
from atd.sim.scene import scene_from_task  # noqa: E402
from benchmarks import bench_robot_interface as timing_loops  # noqa: E402
from benchmarks.bench_robot_interface import bare_loop, interface_loop, use_cpu_time  # noqa: E402
from factories.registry import create  # noqa: E402
from primitives.base import Context  # noqa: E402
from primitives.robot import HandMode  # noqa: E402
from translator import translate  # noqa: E402

TASK = Path(__file__).resolve().parents[1] / "examples" / "pick_and_place.xml"


def idle_machine(seconds: float) -> Estd:
    """One state without controllers, left on a timeout: the executor with nothing to run."""
    timeout = Condition(kind="timeout", params={"seconds": seconds})
    return Estd(
        robot="any", arm="any", initial="idle",
        states=(EstdState(name="idle", type=StateType.MOVE, atd="idle"),
                EstdState(name="done", type=StateType.SUCCESS, atd="done")),
        transitions=(EstdTransition(origin="idle", destination="done", atd="idle->done",
                                    events=(EstdEvent(type=EventType.TIMEOUT, atd="idle->done/timeout",
                                                      condition=timeout),)),),
    )


def timed_run(estd: Estd, factory) -> tuple[Outcome, float, float, float]:
    """The task run as `atd run` does: its outcome, its seconds, those spent in its physics
    steps, and the executor's own (all but the robot interface, physics included).
    Grasping and carrying cost the engine more than the bare loop's robot standing still."""
    run = Run(estd, factory)
    robot, spent = run.robot, {"physics": 0.0, "interface": 0.0}

    def timing(method, account: str):
        def timed(*args):
            start = timing_loops.clock()
            result = method(*args)
            spent[account] += timing_loops.clock() - start
            return result
        return timed

    robot._advance = timing(robot._advance, "physics")
    for name in ("read", "step", "jacobian", "command_arm_velocity", "command_hand"):
        setattr(robot, name, timing(getattr(robot, name), "interface"))
    start = timing_loops.clock()
    outcome = run.execute()
    total = timing_loops.clock() - start
    return outcome, total, spent["physics"], total - spent["interface"]


def profiled(factory, lines: int) -> None:
    """The task run once under cProfile, the functions by time of their own."""
    task, _ = load_task(TASK)
    estd = translate(task, factory).estd
    Run(estd, factory).execute()  # imports, caches: not what a tick costs
    profile = cProfile.Profile()
    run = Run(estd, factory)
    profile.enable()
    outcome = run.execute()
    profile.disable()
    print(f"{factory.info.name}: {outcome.ticks} ticks, {outcome.wall_time:.2f} s under the profiler")
    pstats.Stats(profile).sort_stats("tottime").print_stats(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=3, help="runs per measurement; the fastest counts")
    parser.add_argument("--robot", help="only this robot (default: every robot and arm)")
    parser.add_argument("--profile", type=int, metavar="N",
                        help="instead: profile the task and print the N functions with the most time of their own")
    parser.add_argument("--cpu", action="store_true", help="time in this thread's CPU time, not wall time")
    args = parser.parse_args()
    if args.cpu:
        use_cpu_time()
    if args.profile:
        for robot_name, arm in variants(args.robot):
            profiled(create(robot_name, arm), args.profile)
        return
    task, _ = load_task(TASK)
    scene = scene_from_task(Task(known_objects=task.known_objects, environment=task.environment), TASK)
    print(f"{'robot':<20} {'ticks':>6} {'bare':>14} {'interface':>14} {'empty executor':>15} {'atd run':>14} {'its physics':>14} "
          f"{'its executor':>14} {'run/phys':>9}   us/tick (x bare)")
    for robot_name, arm in variants(args.robot):
        factory = create(robot_name, arm)
        estd = translate(task, factory).estd
        full, spent, physics, own = min((timed_run(estd, factory) for _ in range(args.repeat)), key=lambda r: r[1])
        ticks = full.ticks
        robot = make_robot(factory.robot, scene)
        bare = min(bare_loop(robot, ticks) for _ in range(args.repeat))
        still_hand = (robot.read().hand_q.copy(), HandMode.POSITION)  # the hand held where it is, as arm-only states do
        interface = min(interface_loop(robot, ticks, still_hand) for _ in range(args.repeat))
        robot.close()
        empty = []
        for _ in range(args.repeat):
            robot = make_robot(factory.robot, scene)
            context = Context(info=factory.info, params={})
            executor = Executor(idle_machine(ticks * robot.info.control_period), robot, context)
            start = timing_loops.clock()
            executor.run()
            empty.append(timing_loops.clock() - start)
            robot.close()
        cells = [f"{t / ticks * 1e6:6.1f} ({t / bare:4.2f})"
                 for t in (bare, interface, min(empty), spent, physics, own)]
        print(f"{robot_name + '/' + arm:<20} {ticks:>6} {cells[0]:>14} {cells[1]:>14} {cells[2]:>15} {cells[3]:>14} "
              f"{cells[4]:>14} {cells[5]:>14} {spent / physics:>9.2f}")


if __name__ == "__main__":
    main()
