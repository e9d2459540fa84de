"""What a local pool's worker spends on its first trial beyond the same trial run warm: what it
loads for itself that the forkserver could have loaded once for every worker.

Forks as the pool does, from a process that has imported what the forkserver preloads
(`--preload`, default `atd.campaign.preload`; `atd.campaign.trial` is what it preloaded
before): one child runs trial 0 of tests/data/campaign/small.toml once, another runs it twice.
Wall and CPU time swing on a loaded machine; an instruction count does not. Under cachegrind
each child's count includes its parent's before the fork, so the first trial is child 1 less
the parent, a warm one child 2 less child 1:

    cd /tmp && valgrind --tool=cachegrind --cache-sim=no --cachegrind-out-file=cg.%p \\
        python /path/to/benchmarks/count_worker_start.py [--preload atd.campaign.trial]
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

SPEC = Path(__file__).resolve().parents[1] / "tests" / "data" / "campaign" / "small.toml"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--preload", default="atd.campaign.preload", help="the module the forkserver preloads")
    args = parser.parse_args()
    importlib.import_module(args.preload)
    from atd.campaign.cells import plans
    from atd.campaign.spec import load_spec
    from atd.campaign.trial import run_trial

    loaded, found = load_spec(SPEC)
    if loaded is None:
        raise SystemExit("\n".join(d.render() for d in found))
    plan = next(iter(plans(loaded, trials=1).longest_first()))
    print(f"parent {os.getpid()}: preloaded {args.preload}", flush=True)
    for trials in (1, 2):
        child = os.fork()
        if child == 0:
            started = time.process_time()
            for _ in range(trials):
                record = run_trial(plan)
            print(f"child {os.getpid()}: trial 0 run {trials}x, {time.process_time() - started:.2f} s CPU, "
                  f"{record.summary}", flush=True)
            os._exit(0)
        os.waitpid(child, 0)


if __name__ == "__main__":
    main()
