"""What recording costs: `atd run examples/pick_and_place.xml` on the Melfa in MuJoCo with
and without `--record` at 100 Hz, alternated, measured in one run; and the file's size.

Target (issue 13): the run with recording at most 1.3x the run without. Wall time counts
everything up to the file written; the CPU time of the run's own process is what the
control loop pays, and the writer process's CPU time (on the other core) is shown beside
it: on a shared machine the wall-time ratio depends on whether that core is free.

    python benchmarks/bench_record.py [--repeat 5] [--rate 100]

Times on a shared machine move with its load; instructions do not. `--once
setup|built|bare|recorded` does only that once (the task translated; the run built, not
run; one run without or with recording), for counting instructions under valgrind, each
process (the run's, the writer's) in its own file:

    valgrind --tool=cachegrind --cache-sim=no --cachegrind-out-file=cg.%p \
        python benchmarks/bench_record.py --once recorded
"""

from __future__ import annotations

import argparse
import resource
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from atd.model import load_task  # noqa: E402
from atd.runtime.session import Run  # noqa: E402
from factories.registry import create  # noqa: E402
from translator import translate  # noqa: E402

TASK = Path(__file__).resolve().parents[1] / "examples" / "pick_and_place.xml"
TARGET = 1.3


def _children_cpu() -> float:
    """CPU seconds of the child processes ended so far (the recording's writer)."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=5, help="runs of each; the medians count")
    parser.add_argument("--rate", type=float, default=100.0, help="recording rate, Hz of simulated time")
    parser.add_argument("--once", choices=("setup", "built", "bare", "recorded"),
                        help="do only this, once (for valgrind)")
    args = parser.parse_args()
    task, _ = load_task(TASK)
    factory = create("melfa")
    estd = translate(task, factory).estd
    if args.once:
        with tempfile.TemporaryDirectory() as folder:
            if args.once == "built":
                Run(estd, factory).robot.close()
            elif args.once != "setup":
                record = Path(folder) / "run.mcap" if args.once == "recorded" else None
                Run(estd, factory, record=record, record_rate=args.rate).execute()
        return 0
    bare, recorded, bare_cpu, recorded_cpu, writer_cpu = [], [], [], [], []
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "run.mcap"
        Run(estd, factory).execute()  # warm up
        for _ in range(args.repeat):
            for record, times, cpu in ((None, bare, bare_cpu), (path, recorded, recorded_cpu)):
                started, cpu_started, writer_started = time.perf_counter(), time.process_time(), _children_cpu()
                outcome = Run(estd, factory, record=record, record_rate=args.rate).execute()  # with forking the writer
                times.append(time.perf_counter() - started)
                cpu.append(time.process_time() - cpu_started)
                if record:
                    writer_cpu.append(_children_cpu() - writer_started)
        size = path.stat().st_size
    median = lambda values: sorted(values)[len(values) // 2]  # noqa: E731
    ratio = median(recorded) / median(bare)
    print(f"pick_and_place on melfa in MuJoCo, {outcome.sim_time:.2f} s simulated, {args.repeat} runs each")
    print(f"without recording: {median(bare):.3f} s wall, {median(bare_cpu):.3f} s CPU (medians)")
    print(f"recording at {args.rate:g} Hz: {median(recorded):.3f} s wall, {median(recorded_cpu):.3f} s CPU in the run's "
          f"process, {median(writer_cpu):.3f} s CPU in the writer process (medians), file {size / 1e6:.2f} MB")
    print(f"ratio, wall: {ratio:.2f}x (target <= {TARGET}x)")
    print(f"ratio, CPU of the run's process: {median(recorded_cpu) / median(bare_cpu):.2f}x")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
