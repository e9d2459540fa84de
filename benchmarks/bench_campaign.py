"""Campaign throughput: trials per second with 1, 2 and every core's worth of workers, the
efficiency of each pool against one worker, and the share of a trial spent building and
resetting the robot and scene, measured in one run.

The campaign is tests/data/campaign/small.toml (the Melfa lifting the example cylinder in
MuJoCo under a small approach error) with --trials N. One worker runs in this process;
each pool starts its worker processes inside the timed part, as `atd campaign run` does
(forked from a server that imports the trial code and MuJoCo once per process: the first pool run
pays for that server, as one `atd campaign run` does). Each is run --repeat times, in turn,
and the fastest of each counts, as in the other benchmarks: on a shared VM one run's ratio
ranged from 1.70x to 2.36x within four minutes, the host's noise and not the pool's.

Two figures per pool: the efficiency, trials/s over (workers x one worker's trials/s), which
also counts how much slower each trial runs beside the others (shared caches, memory, other
jobs on the host); and the pool's busy share, the workers' time spent in trials over
workers x wall time, which counts only what the pool itself loses (its start, the wait
between trials, the last trials' tail). Targets (issue 34): 2 workers at least 1.9x one on
2 cores, and at least 85% efficient on every core; set-up at most 20% of a trial (issue 9).

    python benchmarks/bench_campaign.py [--trials 16] [--workers N] [--repeat 3]
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from atd.campaign.cells import plans  # noqa: E402
from atd.campaign.record import TrialRecord  # noqa: E402
from atd.campaign.runner import run_local  # noqa: E402
from atd.campaign.spec import load_spec  # noqa: E402

SPEC = Path(__file__).resolve().parents[1] / "tests" / "data" / "campaign" / "small.toml"
SPEEDUP_TARGET = 1.9  # 2 workers over 1, on 2 cores
EFFICIENCY_TARGET = 0.85  # on every core
SETUP_TARGET = 0.20


def timed(workers: int, trials: int) -> tuple[float, list[TrialRecord]]:
    """Wall-clock seconds for the campaign on `workers`, and its records."""
    loaded, found = load_spec(SPEC)
    if loaded is None:
        raise SystemExit("\n".join(d.render() for d in found))
    records: list[TrialRecord] = []
    started = time.perf_counter()
    run_local(plans(loaded, trials=trials).longest_first(), workers, records.append)
    return time.perf_counter() - started, records


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--trials", type=int, default=16, help="trials in the campaign")
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1,
                        help="the largest pool (default: every core); 1 and 2 workers are measured too")
    parser.add_argument("--repeat", type=int, default=3, help="runs of each; the fastest counts")
    args = parser.parse_args()
    sizes = sorted({1, min(2, args.workers), args.workers})
    load = os.getloadavg()[0]  # other jobs on the host: with more than the cores busy, efficiency means little
    timed(1, 1)  # warm up: imports, the first translation
    best: dict[int, tuple[float, list[TrialRecord]]] = {}
    for _ in range(args.repeat):
        for size in sizes:
            run = timed(size, args.trials)
            if size not in best or run[0] < best[size][0]:
                best[size] = run
    one = best[1][0]
    print(f"campaign: {SPEC.name}, {args.trials} grasp-and-lift trials (melfa, MuJoCo), fastest of {args.repeat} "
          f"runs each, {os.cpu_count()} cores, load average before: {load:.1f}")
    print(f"{'workers':>8} {'wall s':>8} {'trials/s':>9} {'speed-up':>9} {'efficiency':>11} {'pool busy':>10} "
          f"{'mean trial s':>13}")
    for size in sizes:
        wall, records = best[size]
        busy = sum(r.wall_time for r in records) / (size * wall)
        print(f"{size:>8} {wall:8.2f} {args.trials / wall:9.2f} {one / wall:8.2f}x {one / wall / size:10.0%} "
              f"{busy:10.0%} {sum(r.wall_time for r in records) / len(records):13.2f}")
    for size in sizes[1:]:
        speedup = one / best[size][0]
        target = f"target >= {SPEEDUP_TARGET}x on 2 cores" if size == 2 else f"target >= {EFFICIENCY_TARGET:.0%}"
        print(f"speed-up, {size} workers over 1: {speedup:.2f}x, efficiency {speedup / size:.0%} ({target})")
    records = best[1][1]
    setup = sum(r.setup_time for r in records) / sum(r.wall_time for r in records)
    print(f"set-up (build and reset robot and scene) per trial: {setup:.1%} of the trial (target <= {SETUP_TARGET:.0%})")
    print(f"mean trial alone: {sum(r.wall_time for r in records) / len(records):.2f} s wall, "
          f"{sum(r.sim_time for r in records) / len(records):.2f} s simulated")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
