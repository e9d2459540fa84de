"""How well, and how fast, thesis 3.4.3's generators and the explore primitive do on the
scripted box worlds of the tests (tests/primitives/box_worlds.py: the Melfa beside a
24 x 20 x 8 cm box): per engine and world, what each found, how far its approach lies from
the nearest object's true centre (x y), and the simulated and wall-clock time it took.

    python benchmarks/bench_perception.py [--engine mujoco pybullet] [--methods explore vision blind_exploration]

Wall times move with the machine's load; the errors do not.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from atd.model.vocabulary import EventType  # noqa: E402
from tests.primitives.box_worlds import CORNER, FLOOR, MELFA_REACH, box_world, cube, perceive  # noqa: E402
from tests.primitives.conftest import Stage, execute, leaf, machine, use  # noqa: E402

WORLDS = {
    "corner": lambda: (cube("block", CORNER),),
    "empty": lambda: (),
    "two apart": lambda: (cube("a", (0.12, 0.1)), cube("b", (0.24, 0.2))),
    "touching, one taller": lambda: (cube("tall", (0.15, 0.15)), cube("flat", (0.2005, 0.15), height=0.02)),
    "touching, alike": lambda: (cube("a", (0.15, 0.15)), cube("b", (0.2005, 0.15))),
}


def _perceive(method: str, engine: str, world: str) -> tuple[str, str, float, float]:
    robot = box_world(*WORLDS[world](), engine=engine)
    truth = [pose[:3, 3] for pose in robot.object_poses().values()]
    stage = Stage(perceive(method), use("hand_shape", shape="closed"), leaf("object_found", value="found"),
                  seconds=120.0)
    estd = machine(stage, failures={"s0": (EventType.ERROR, leaf("nothing_found", value="found"))})
    started = time.perf_counter()
    outcome, executor = execute(estd, robot)
    wall = time.perf_counter() - started
    robot.close()
    found = executor.machine.base.memory.get("found")
    if not hasattr(found, "point"):
        return "nothing found", "", outcome.sim_time, wall
    error = min(float(np.linalg.norm(found.point[:2] - t[:2])) for t in truth) if truth else float("nan")
    seen = "" if found.candidates is None else f", {found.candidates} seen"
    return f"found, top z {found.point[2]:.3f}{seen}", f"{error * 100:.1f} cm", outcome.sim_time, wall


def _explore(engine: str) -> list[tuple[str, str, str, float, float]]:
    """Down onto the corner cube's top and onto the floor, jaws closed: the contact's
    height less the fingertips' reach, against the surface's."""
    robot = box_world(cube("block", CORNER), engine=engine)
    top = float(robot.object_poses()["block"][2, 3]) + 0.025
    rows = []
    for name, xy, surface in (("the cube's top", CORNER, top), ("the floor", (0.13, 0.12), FLOOR)):
        closed = use("hand_shape", shape="closed")
        estd = machine(Stage(use("cartesian_move", target=(*xy, 0.16)), closed, leaf("arm_done")),
                       Stage(use("explore", direction=(0.0, 0.0, -1.0), writes="touched"), closed, leaf("arm_done")))
        started = time.perf_counter()
        outcome, executor = execute(estd, robot)
        wall = time.perf_counter() - started
        touched = executor.machine.base.memory["touched"]
        error = float(touched.point[2]) - MELFA_REACH - surface
        rows.append((f"explore down to {name}", f"{touched.sensor} {touched.force:.1f} N",
                     f"{error * 1000:+.1f} mm in z", outcome.sim_time, wall))
    robot.close()
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--engine", nargs="+", default=["mujoco", "pybullet"])
    parser.add_argument("--methods", nargs="+", default=["explore", "vision", "blind_exploration"])
    args = parser.parse_args()
    print(f"{'engine':9} {'what':44} {'result':30} {'error':14} {'sim s':>6} {'wall s':>6}")
    for engine in args.engine:
        rows = _explore(engine) if "explore" in args.methods else []
        for method in (m for m in args.methods if m != "explore"):
            worlds = ("corner", "empty") if method == "blind_exploration" else tuple(WORLDS)
            rows += [(f"{method}: {world}", *_perceive(method, engine, world)) for world in worlds]
        for what, result, error, sim, wall in rows:
            print(f"{engine:9} {what:44} {result:30} {error:14} {sim:6.2f} {wall:6.2f}")


if __name__ == "__main__":
    main()
