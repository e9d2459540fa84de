"""One pick-and-place run, in-process, for an instruction counter: on a machine other jobs
load, wall and CPU time swing by more than a change to the tick saves, an instruction count
does not. The run's own count is the whole count less that of its setup alone (`--setup`:
imports, translation, the engine's model), counted the same way:

    valgrind --tool=cachegrind --cache-sim=no python benchmarks/count_tick.py --robot melfa
    valgrind --tool=cachegrind --cache-sim=no python benchmarks/count_tick.py --robot melfa --setup

(`atd run` forks the run into a child process, which `python -m cProfile` does not follow:
profile `bench_tick.py --profile` or this script instead.)
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from atd.model import load_task  # noqa: E402
from atd.runtime.session import Run  # noqa: E402
from factories.registry import create  # noqa: E402
from translator import translate  # noqa: E402

TASK = Path(__file__).resolve().parents[1] / "examples" / "pick_and_place.xml"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--robot", default="melfa")
    parser.add_argument("--arm", default="main")
    parser.add_argument("--setup", action="store_true", help="stop before the run: its setup alone")
    args = parser.parse_args()
    task, _ = load_task(TASK)
    factory = create(args.robot, args.arm)
    run = Run(translate(task, factory).estd, factory)
    if not args.setup:
        outcome = run.execute()
        print(f"{args.robot}/{args.arm}: {outcome.ticks} ticks, {outcome.summary}")


if __name__ == "__main__":
    main()
