"""Real-time factor of `atd run examples/pick_and_place.xml`, per robot and engine, against a
bare engine stepping loop on the same scene, measured in the same run.

For each robot (and arm) and engine: the task is translated and run through the executor
(every primitive, condition and sensor, as `atd run` does, minus printing); then a fresh
robot in the same scene is stepped by the engine alone for as many control ticks. Prints
both real-time factors (simulated seconds per wall-clock second) and their ratio, which is
the cost of the whole executor over bare physics. Targets (issue 5): MuJoCo pick-and-place at
least 20x real time; executor at most 1.30x bare stepping.

    python benchmarks/bench_run.py [--repeat 3] [--engine mujoco|pybullet] [--robot melfa]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from atd.model import Task, load_task  # noqa: E402
from atd.runtime.session import Run  # noqa: E402
from atd.sim import ENGINES, make_robot, variants  # noqa: E402
from atd.sim.scene import scene_from_task  # noqa: E402
from benchmarks.bench_robot_interface import bare_loop  # noqa: E402
from factories.registry import create  # noqa: E402
from translator import translate  # noqa: E402

TASK = Path(__file__).resolve().parents[1] / "examples" / "pick_and_place.xml"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=3, help="runs per measurement; the fastest counts")
    parser.add_argument("--engine", choices=ENGINES, action="append", help="engines to measure (default: both)")
    parser.add_argument("--robot", help="only this robot (default: every robot and arm)")
    args = parser.parse_args()
    task, _ = load_task(TASK)
    scene = scene_from_task(Task(known_objects=task.known_objects, environment=task.environment), TASK)
    print(f"{'robot':<20} {'engine':<9} {'outcome':<8} {'sim s':>6} {'atd run x rt':>13} {'bare x rt':>10} {'ratio':>6}")
    for robot_name, arm in variants(args.robot):
        factory = create(robot_name, arm)
        estd = translate(task, factory).estd
        for engine in args.engine or ENGINES:
            best_wall, outcome = None, None
            for _ in range(args.repeat):
                outcome = Run(estd, factory, engine=engine).execute()
                best_wall = min(best_wall or outcome.wall_time, outcome.wall_time)
            bare = make_robot(factory.robot, scene, engine)
            bare_wall = min(bare_loop(bare, outcome.ticks) for _ in range(args.repeat))
            bare.close()
            ours, theirs = outcome.sim_time / best_wall, outcome.sim_time / bare_wall
            verdict = "success" if outcome.succeeded else "failure"
            print(f"{robot_name + '/' + arm:<20} {engine:<9} {verdict:<8} {outcome.sim_time:6.2f} {ours:12.1f}x "
                  f"{theirs:9.1f}x {theirs / ours:6.2f}")


if __name__ == "__main__":
    main()
