"""How often the slide (thesis 3.3.5) carries its object, and whether it says so truthfully
(issue 33: at least 9 of 10 per robot, zero false successes).

The tray of tests/data/slide_tray.xml is placed a little away from where the task says
(uniform +-1.5 cm in x and y, +-10 deg about z, seeded per run: the robot still believes the
task's pose), then slid 8 cm. Carried: by ground truth its centre ends within 2 cm of its
target, where the task's pose moved by the slide's 8 cm puts it. A false success is a
success said without that.

    python benchmarks/bench_slide.py [--runs 10] [--engine mujoco|pybullet] [--seed 1000]
                                     [--arms baxter:right,baxter:left,tombatossals:right,tombatossals:left]
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import sys
from collections import Counter
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from atd.model import load_task  # noqa: E402
from atd.runtime.executor import Executor  # noqa: E402
from atd.sim import load_description, make_robot  # noqa: E402
from atd.sim.scene import scene_from_task  # noqa: E402
from factories.registry import create  # noqa: E402
from primitives.base import Context  # noqa: E402
from translator import translate  # noqa: E402

TRAY = Path(__file__).resolve().parents[1] / "tests" / "data" / "slide_tray.xml"
SLID = np.array([0.0, 0.08])  # m the slide's path moves the hand: the tray should follow
CARRIED = 0.02  # m: issue 33's "within 2 cm of its target"
SHIFT = 0.015  # m of displacement, each way, in x and y
TURN = 10.0  # deg of displacement about z, each way


def displaced(body, seed: int):
    """The tray's truth for one run, moved a little from where the task says."""
    rng = np.random.default_rng(seed)
    dx, dy = rng.uniform(-SHIFT, SHIFT, 2)
    yaw = math.radians(rng.uniform(-TURN, TURN))
    pose = body.pose.copy()
    pose[:2, :2] = [[math.cos(yaw), -math.sin(yaw)], [math.sin(yaw), math.cos(yaw)]]
    pose[:2, 3] += (dx, dy)
    return dataclasses.replace(body, pose=pose)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=10)
    parser.add_argument("--engine", default="mujoco")
    parser.add_argument("--seed", type=int, default=1000, help="run i displaces the tray by seed + i")
    parser.add_argument("--arms", default="baxter:right,baxter:left,tombatossals:right,tombatossals:left")
    args = parser.parse_args()
    task, _ = load_task(TRAY)
    for robot, arm in (a.split(":") for a in args.arms.split(",")):
        estd = translate(task, create(robot, arm)).estd
        if estd is None:  # a robot that cannot find where the object stands refuses to slide it
            print(f"{robot}/{arm}: refused", flush=True)
            continue
        said = carried = false = 0
        ends: Counter[str] = Counter()
        misses = []  # (run, cm from the target, cm the tray travelled) of every run not carried
        for run in range(args.runs):
            scene = scene_from_task(task, TRAY)
            body = displaced(scene.objects[0], args.seed + run)
            sim = make_robot(load_description(robot, arm), dataclasses.replace(scene, object=body), args.engine)
            context = Context(info=sim.info, params={}, object=task.object, environment=task.environment)
            executor = Executor(estd, sim, context, budget=60.0)
            outcome = executor.run()
            target = scene.objects[0].pose[:2, 3] + SLID
            off = float(np.linalg.norm(sim.object_pose()[:2, 3] - target))
            ok = off < CARRIED
            if not ok:
                travel = float(np.linalg.norm(sim.object_pose()[:2, 3] - body.pose[:2, 3]))
                misses.append((run, round(off * 100, 1), round(travel * 100, 1)))
            said += outcome.succeeded
            carried += ok
            false += outcome.succeeded and not ok
            ends[outcome.summary if outcome.succeeded else _why(executor)] += 1
        print(f"{args.engine} {robot}/{arm}: {args.runs} runs, success said {said}, carried within 2 cm {carried}, "
              f"false successes {false}; ends: {dict(ends)}; not carried (run, cm off, cm travelled): {misses}",
              flush=True)


def _why(executor: Executor) -> str:
    """The first words of the reason behind the last event, e.g. 'moved nothing'."""
    last = [r for r in executor.trace.records if r["type"] == "event"][-1]
    reasons = [c["reason"] for c in last["conditions"] if c.get("reason")]
    return reasons[0].split(":")[0] if reasons else last["event"]


if __name__ == "__main__":
    main()
