"""How often the unscrew primitive (thesis 3.3.6) really takes the cap off a screw-capped
bottle standing in a fixture, with and without its reactive alignment: runs of
examples/unscrew_fixture.xml on one robot arm and engine, the bottle truly standing up to
`--noise` m off where the task believes it (uniform per axis, seeded per run: thesis
Table 3.5 adds 1.5 cm). Per run: the task's verdict, the simulator's (the cap off its
thread), twists made and simulated time; per setting the counts and false successes (the
task says the cap is off, the simulator disagrees).

`--objects all` runs each of the eight screw-capped objects of the library in the fixture
instead, as examples/campaigns/unscrew.toml does: the robot believes the library object
(its class, size, weight) standing where the task's object stands, and the task is
otherwise as written; the task finds the cap's height itself (a gripper:
`--task examples/unscrew_fixture_jaws.xml`).

    python benchmarks/bench_unscrew.py [--runs 5] [--noise 0.0] [--robot tombatossals --arm left] [--engine mujoco]
    python benchmarks/bench_unscrew.py --robot melfa --arm "" --task examples/unscrew_fixture_jaws.xml --objects all
"""

from __future__ import annotations

import argparse
import re
import sys
import tempfile
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from atd.campaign.unscrew import twists_said  # noqa: E402
from atd.model import load_task  # noqa: E402
from atd.sim.library import get, library  # noqa: E402
from atd.runtime.session import Run, world_scene  # noqa: E402
from factories.registry import create  # noqa: E402
from translator import translate  # noqa: E402

TASK = REPO / "examples" / "unscrew_fixture.xml"
WORLD = REPO / "examples" / "unscrew_fixture.world.toml"


def _world(place: np.ndarray, folder: Path, thing: str | None = None) -> Path:
    """The example's world with the bottle standing at `place` (x, y, m), and `thing` (a
    library object) in place of the jam jar."""
    text = WORLD.read_text() if thing is None else WORLD.read_text().replace('"jam_jar"', f'"{thing}"')
    match = re.search(r"position = \[([-\d.]+), ([-\d.]+)\]", text)
    path = folder / "world.toml"
    path.write_text(text.replace(match.group(0), f"position = [{place[0]:.6f}, {place[1]:.6f}]"))
    return path


def trial(robot: str, arm: str, engine: str, alignment: bool, noise: float, index: int,
          task_path: Path = TASK, thing: str | None = None) -> dict:
    factory = create(robot, arm=arm or None)
    task, _ = load_task(task_path)
    believed = task.object.pose.as_array()[:2, 3]
    if thing is not None:  # what the campaign believes of a library object in the task's place
        task = task.model_copy(update={"object": get(thing).object_info(float(believed[0]), float(believed[1]))})
    state = task.states_by_name["unscrew_cap"]
    unscrew = state.model_copy(update={"parameters": {**state.parameters, "alignment": str(alignment).lower()}})
    task = task.model_copy(update={"states": tuple(unscrew if s.name == "unscrew_cap" else s for s in task.states)})
    estd = translate(task, factory).estd
    offset = np.random.default_rng(index).uniform(-noise, noise, 2)
    caps: dict = {}
    with tempfile.TemporaryDirectory() as folder:
        truth = world_scene(estd, _world(believed + offset, Path(folder), thing), index)
        run = Run(estd, factory, engine=engine, seed=index, scene=truth)
        outcome = run.execute(afterwards=lambda sim: caps.update(sim.caps()))
    [cap] = caps.values()
    said = [n for r in run.trace.records if r["type"] == "event" for n in twists_said(r)]
    moves = said[-1] if said else None  # None: ended on a timeout, uncounted
    return {"task": outcome.succeeded, "off": bool(cap.free), "moves": moves, "time": outcome.sim_time,
            "offset": offset, "summary": outcome.summary}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--noise", type=float, default=0.0)
    parser.add_argument("--robot", default="tombatossals")
    parser.add_argument("--arm", default="left")
    parser.add_argument("--engine", default="mujoco")
    parser.add_argument("--alignment", choices=("on", "off", "both"), default="both")
    parser.add_argument("--task", type=Path, default=TASK)
    parser.add_argument("--objects", default="example", help="example, all, or one library object's name")
    args = parser.parse_args()
    settings = {"on": [True], "off": [False], "both": [False, True]}[args.alignment]
    capped = [n for n, o in library().items() if o.thread is not None]
    things = {"example": [None], "all": capped}.get(args.objects, [args.objects])
    for alignment in settings:
        results = []
        for index, thing in [(i, t) for t in things for i in range(args.runs)]:
            r = trial(args.robot, args.arm, args.engine, alignment, args.noise, index, args.task, thing)
            results.append(r)
            print(f"{thing or 'example'} alignment {'on' if alignment else 'off'} run {index}: "
                  f"offset {r['offset'].round(4).tolist()} "
                  f"task {'ok' if r['task'] else 'FAILED'}, cap {'off' if r['off'] else 'ON'}, "
                  f"{r['moves']} twists, {r['time']:.1f} s: {r['summary']}", flush=True)
        counted = [r["moves"] for r in results if r["moves"] is not None]
        n = len(results)
        ok, off = sum(r["task"] for r in results), sum(r["off"] for r in results)
        false = sum(r["task"] and not r["off"] for r in results)
        print(f"== {args.robot}/{args.arm} {args.engine} noise {args.noise} alignment {'on' if alignment else 'off'}: "
              f"task success {ok}/{n}, cap off {off}/{n}, false successes {false}, "
              f"mean twists {np.mean(counted) if counted else float('nan'):.1f} (of {len(counted)} counted), "
              f"mean time {np.mean([r['time'] for r in results]):.1f} s", flush=True)


if __name__ == "__main__":
    main()
