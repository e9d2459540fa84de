"""Campaign throughput: trials per second with one worker and with every core, and the
share of a trial spent building and resetting the robot and scene, measured in one run.

The campaign is tests/data/campaign/small.toml (the Melfa lifting the example cylinder in
MuJoCo under a small approach error) with --trials N. One worker runs in this process;
the pool starts its worker processes inside the timed part, as `atd campaign run` does
(forked from a server that imports the trial code once per process: the first pool run
pays for that server, as one `atd campaign run` does).
Each is run --repeat times, alternately, and the fastest of each counts, as in the other
benchmarks: on this shared VM one run's ratio ranged from 1.70x to 2.36x within four
minutes, the host's noise and not the pool's. Targets (issue 9): every core at least
1.8x one worker on a 2-core machine; set-up at most 20% of a grasp-and-lift trial.

    python benchmarks/bench_campaign.py [--trials 24] [--workers N] [--repeat 3]
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
SPEEDUP_TARGET = 1.8
SETUP_TARGET = 0.20


def timed(workers: int, trials: int) -> tuple[float, list[TrialRecord]]:
    """Wall-clock seconds for the campaign on `workers`, and its records."""
    loaded, found = load_spec(SPEC)
    if loaded is None:
        raise SystemExit("\n".join(d.render() for d in found))
    records: list[TrialRecord] = []
    started = time.perf_counter()
    run_local(plans(loaded, trials=trials), workers, records.append)
    return time.perf_counter() - started, records


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--trials", type=int, default=24, help="trials in the campaign")
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1, help="the pool's size (default: cores)")
    parser.add_argument("--repeat", type=int, default=3, help="runs of each; the fastest counts")
    args = parser.parse_args()
    timed(1, 1)  # warm up: imports, the first translation
    runs = [(timed(1, args.trials), timed(args.workers, args.trials)) for _ in range(args.repeat)]
    one, records = min((alone for alone, _ in runs), key=lambda run: run[0])
    many, pooled = min((pool for _, pool in runs), key=lambda run: run[0])
    setup = sum(r.setup_time for r in records) / sum(r.wall_time for r in records)
    speedup = one / many
    print(f"campaign: {SPEC.name}, {args.trials} grasp-and-lift trials (melfa, MuJoCo), fastest of {args.repeat} runs each")
    print(f"{'workers':>8} {'wall s':>8} {'trials/s':>9}")
    print(f"{1:>8} {one:8.2f} {args.trials / one:9.2f}")
    print(f"{args.workers:>8} {many:8.2f} {args.trials / many:9.2f}")
    print(f"speed-up, {args.workers} workers over 1: {speedup:.2f}x (target >= {SPEEDUP_TARGET}x)")
    print(f"set-up (build and reset robot and scene) per trial: {setup:.1%} of the trial (target <= {SETUP_TARGET:.0%})")
    print(f"mean trial: {sum(r.wall_time for r in records) / len(records):.2f} s wall, "
          f"{sum(r.sim_time for r in records) / len(records):.2f} s simulated")
    # A trial slower beside another than alone is the cores' (shared cache, the host), not the pool's.
    print(f"mean trial wall with {args.workers} workers: {sum(r.wall_time for r in pooled) / len(pooled):.2f} s; "
          f"the pool's own cost (start, last trial's wait): "
          f"{many - sum(r.wall_time for r in pooled) / args.workers:.2f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
