"""What one empty-the-box trial (thesis 3.4.3) costs, against its own world's physics.

Runs one trial of `examples/campaigns/empty_the_box.toml` in this process, as a campaign's
worker does (`atd.campaign.trial.run_trial`: the five objects dropped and settled, the
robot's perception, the judge), then steps the same trial's world with the robot holding
still for as many control ticks as the trial ran (`physics alone`: its robot, box and five
objects, no executor, no sensors read). Prints the CPU seconds of each, their ratio and the
trial's real-time factor:

    python benchmarks/bench_box.py --task vision --robot melfa --engine mujoco --budget 120

A box trial's records are its trace and its record; `--dump FILE` writes both as JSON
(the record without its wall and setup times) for comparing two trees' runs of one trial.

Where the time goes: `--profile N` runs the trial under cProfile and prints the N functions
with the most time of their own, then the time below each layer's entry points. Where other
jobs load the machine, count instructions instead, the trial less its setup (`--setup`:
imports, translation, the world's drop and settling, the run built):

    valgrind --tool=cachegrind --cache-sim=no python benchmarks/bench_box.py --task vision --budget 120 --once
    valgrind --tool=cachegrind --cache-sim=no python benchmarks/bench_box.py --task vision --budget 120 --setup
"""

from __future__ import annotations

import argparse
import cProfile
import json
import math
import pstats
import sys
import time
from dataclasses import asdict, fields
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from atd.campaign import trial  # noqa: E402
from atd.campaign.cells import TrialPlan, parse_only, plans  # noqa: E402
from atd.campaign.record import TrialRecord  # noqa: E402
from atd.campaign.spec import load_spec  # noqa: E402
from atd.runtime.session import Run  # noqa: E402
from factories.registry import factory_class  # noqa: E402

SPEC = Path(__file__).resolve().parents[1] / "examples" / "campaigns" / "empty_the_box.toml"
TASKS = {"random": "empty_the_box_random", "exploration": "empty_the_box_exploration", "vision": "empty_the_box_vision"}
#: Each layer's entry point (file, function), for `--profile`'s cumulative times; some hold
#: others (the settling steps the physics, a tick of the machine runs perception).
LAYERS = {
    "physics steps, settling's too": ("_engine.py", "_advance"),
    "settling the dropped world": ("simrobot.py", "settle"),
    "sampling the sensors": ("simrobot.py", "_sample"),
    "a machine's tick (all below)": ("executor.py", "tick"),
    "  its conditions": ("executor.py", "_fired"),
    "  a depth picture": ("simrobot.py", "capture"),
    "  the point cloud's clusters": ("generators.py", "objects_seen"),
    "arbitration and commands": ("executor.py", "_apply"),
    "the judge watching": ("judge.py", "watch"),
}


class _Unhurried(TrialPlan):
    """A trial without its wall-clock watchdog: under a profiler or an instruction counter it
    runs tens of times slower than a campaign allows, and the same simulated trial is wanted."""

    @property
    def wall_limit(self) -> float:
        return math.inf


class _Kept(Run):
    """A `Run` that keeps itself, so the bench can read the trial's trace after it, and adds
    the CPU time of its physics steps (`_advance`; the world's settling is before) to `physics`."""

    made: list[Run] = []
    physics = 0.0

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        _Kept.made.append(self)
        advance = self.robot._advance

        def timed() -> None:
            start = time.thread_time()
            advance()
            _Kept.physics += time.thread_time() - start

        self.robot._advance = timed


def the_plan(args: argparse.Namespace) -> TrialPlan:
    """The one trial the options name, from the spec with its base seed and budget as given."""
    loaded, diagnostics = load_spec(SPEC)
    assert loaded is not None, diagnostics
    update = {k: v for k, v in (("base_seed", args.seed), ("budget", args.budget)) if v is not None}
    loaded = loaded.model_copy(update={"spec": loaded.spec.model_copy(update=update)})
    arm = args.arm or factory_class(args.robot).arms[0].name
    only = parse_only((f"task={TASKS[args.task]}", f"robot={args.robot}", f"arm={arm}", f"engine={args.engine}"))
    [plan] = [p for p in plans(loaded, only, args.index + 1) if p.index == args.index]
    return _Unhurried(**{f.name: getattr(plan, f.name) for f in fields(plan)})


def kept_trial(plan: TrialPlan) -> tuple[TrialRecord, Run]:
    """The trial's record, as a campaign stores it, and its run."""
    trial.Run, _Kept.made, _Kept.physics = _Kept, [], 0.0
    try:
        record = trial.run_trial(plan)
    finally:
        trial.Run = Run
    assert record.status == "ok", record.error
    return record, _Kept.made[0]


def physics_alone(plan: TrialPlan, ticks: int) -> float:
    """CPU seconds for the trial's world (settled as the trial's was) to step `ticks`
    control periods with the robot holding still: the engine's own cost of this world."""
    run, _ = trial.trial_run(plan, TrialRecord(cell=plan.cell, index=plan.index, seed=plan.seed))
    robot = run.robot
    hold, zero = robot.read().arm_q.copy(), robot._zero
    start = time.thread_time()
    for _ in range(ticks):
        robot._apply_arm(hold, zero)
        robot._advance()
    spent = time.thread_time() - start
    robot.close()
    return spent


def dump(path: Path, record: TrialRecord, run: Run) -> None:
    """The trial's trace and record (but its wall and setup times) as JSON."""
    kept = asdict(record)
    kept.pop("wall_time"), kept.pop("setup_time")
    path.write_text(json.dumps({"record": kept, "trace": run.trace.records}, indent=1,
                               default=lambda o: o.tolist() if hasattr(o, "tolist") else repr(o)))


def profiled(plan: TrialPlan, lines: int) -> None:
    """The trial under cProfile: the functions by time of their own, then by layer."""
    profile = cProfile.Profile(time.thread_time)  # CPU time: other jobs load this machine
    profile.enable()
    record, run = kept_trial(plan)
    profile.disable()
    stats = pstats.Stats(profile)
    print(f"{plan.cell.key} #{plan.index}: {record.sim_time:.1f} s simulated, {record.wall_time:.1f} s under the "
          f"profiler ({record.setup_time:.1f} s setup); {record.summary}")
    stats.sort_stats("tottime").print_stats(lines)
    total = stats.total_tt
    print(f"{'layer':<30} {'s':>8} {'share':>6}   (cumulative under its entry points; of {total:.1f} s)")
    for layer, (where, function) in LAYERS.items():
        spent = sum(ct for (file, _, name), (_, _, _, ct, _) in stats.stats.items()
                    if name == function and file.endswith(where))
        print(f"{layer:<30} {spent:8.2f} {spent / total:6.1%}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--task", choices=sorted(TASKS), default="vision", help="the approach-vector generator")
    parser.add_argument("--robot", default="melfa")
    parser.add_argument("--arm", help="default: the robot's first")
    parser.add_argument("--engine", default="mujoco", choices=("mujoco", "pybullet"))
    parser.add_argument("--index", type=int, default=0, help="the trial's number in its cell")
    parser.add_argument("--seed", type=int, help="the spec's base seed instead of its own")
    parser.add_argument("--budget", type=float, help="simulated seconds instead of the spec's 600")
    parser.add_argument("--dump", type=Path, metavar="FILE", help="write the trial's trace and record as JSON")
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument("--profile", type=int, metavar="N", help="profile the trial; print the N dearest functions")
    mode.add_argument("--once", action="store_true", help="run the trial, nothing else (for an instruction counter)")
    mode.add_argument("--setup", action="store_true", help="build the trial's run, no more (its setup alone)")
    args = parser.parse_args()
    plan = the_plan(args)
    if args.setup:
        trial.trial_run(plan, TrialRecord(cell=plan.cell, index=plan.index, seed=plan.seed))[0].robot.close()
        return
    if args.profile:
        profiled(plan, args.profile)
        return
    start = time.thread_time()
    record, run = kept_trial(plan)
    spent = time.thread_time() - start
    if args.dump:
        dump(args.dump, record, run)
    print(f"{plan.cell.key} #{plan.index} (seed {plan.seed}): {record.summary}; "
          f"{record.measurements.get('attempts', 0):.0f} attempts, judged {record.judge_reason}; {run.robot.settling}")
    if args.once:
        return
    ticks = round(record.sim_time / run.robot.info.control_period)
    physics = physics_alone(plan, ticks)
    print(f"trial: {spent:.2f} s CPU for {record.sim_time:.1f} s simulated ({record.sim_time / spent:.2f}x real time), "
          f"of which its physics steps {_Kept.physics:.2f} s ({_Kept.physics / spent:.0%}); physics alone (the "
          f"robot still), {ticks} ticks: {physics:.2f} s CPU; trial/physics alone {spent / physics:.2f}")


if __name__ == "__main__":
    main()
