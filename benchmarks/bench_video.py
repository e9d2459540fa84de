"""What a video costs: `atd run examples/pick_and_place.xml` on the Melfa in MuJoCo with and
without `--video` (a GIF at 640x480 by default), alternated, measured in one run; and the
file's size.

Targets (issue 35): the run with the video at most 2x the run without; the GIF under 1 MB.
Wall time counts everything up to the file written. Frames are rendered every 0.1 s of
simulated time, so the cost grows with the run's simulated length, not with its ticks, in
a process of their own (atd/sim/video_recorder.py), whose CPU time is shown beside the
run's: on a machine without a GPU, rendering is software OpenGL (llvmpipe) and costs about
what the simulation does, so the wall-time ratio depends on whether a second core is free.

    python benchmarks/bench_video.py [--repeat 3] [--size 640x480] [--format gif|mp4]
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
from atd.sim.video import parse_size  # noqa: E402
from factories.registry import create  # noqa: E402
from translator import translate  # noqa: E402

TASK = Path(__file__).resolve().parents[1] / "examples" / "pick_and_place.xml"
TARGET = 2.0
SIZE_TARGET = 1e6  # bytes, for the GIF


def _children_cpu() -> float:
    """CPU seconds of the child processes ended so far (the rendering processes)."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=3, help="runs of each; the medians count")
    parser.add_argument("--size", default="640x480", help="the video's WIDTHxHEIGHT")
    parser.add_argument("--format", choices=("gif", "mp4"), default="gif")
    args = parser.parse_args()
    size = parse_size(args.size)
    task, _ = load_task(TASK)
    factory = create("melfa")
    estd = translate(task, factory).estd
    bare, filmed, bare_cpu, filmed_cpu, render_cpu = [], [], [], [], []
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / f"run.{args.format}"
        Run(estd, factory).execute()  # warm up
        for _ in range(args.repeat):
            for video, times, cpu in ((None, bare, bare_cpu), (path, filmed, filmed_cpu)):
                started, cpu_started, render_started = time.perf_counter(), time.process_time(), _children_cpu()
                session = Run(estd, factory, video=video, video_size=size)
                outcome = session.execute()
                times.append(time.perf_counter() - started)
                cpu.append(time.process_time() - cpu_started)
                if video:
                    render_cpu.append(_children_cpu() - render_started)
        file_size = path.stat().st_size
        note = session.notes[-1]
    median = lambda values: sorted(values)[len(values) // 2]  # noqa: E731
    ratio = median(filmed) / median(bare)
    print(f"pick_and_place on melfa in MuJoCo, {outcome.sim_time:.2f} s simulated, {args.repeat} runs each")
    print(f"without video: {median(bare):.3f} s wall, {median(bare_cpu):.3f} s CPU (medians)")
    print(f"with video:    {median(filmed):.3f} s wall, {median(filmed_cpu):.3f} s CPU in the run's process, "
          f"{median(render_cpu):.3f} s CPU in the rendering process (medians); {note}")
    print(f"file: {file_size / 1e6:.3f} MB" + (f" (target < {SIZE_TARGET / 1e6:g} MB)" if args.format == "gif" else ""))
    print(f"ratio, wall: {ratio:.2f}x (target <= {TARGET}x)")
    print(f"ratio, CPU of the run's process: {median(filmed_cpu) / median(bare_cpu):.2f}x")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
