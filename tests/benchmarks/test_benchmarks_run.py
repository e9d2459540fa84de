"""The benchmarks still run against today's code (they time nothing here: they only have to
finish and print their table, so a changed interface cannot leave one broken unnoticed)."""

from __future__ import annotations

import subprocess
import sys

import pytest

from tests.conftest import REPO


@pytest.mark.parametrize(("script", "args", "row"), [
    ("bench_tick.py", ("--repeat", "1", "--robot", "melfa", "--cpu"), "melfa/main"),
    ("bench_run.py", ("--repeat", "1", "--engine", "mujoco", "--robot", "melfa"), "melfa/main"),
    ("bench_robot_interface.py", ("--seconds", "0.05", "--repeat", "1", "--robot", "melfa"), "worst overhead ratio"),
    ("bench_campaign.py", ("--trials", "2", "--workers", "2", "--repeat", "1"), "speed-up, 2 workers over 1"),
    ("bench_record.py", ("--repeat", "1",), "recording at 100 Hz"),
    ("bench_video.py", ("--repeat", "1", "--size", "320x240"), "ratio, wall"),
    ("bench_perception.py", ("--engine", "mujoco", "--methods", "vision"), "vision: corner"),
    ("bench_box.py", ("--task", "random", "--budget", "5"), "trial/physics alone"),
    ("bench_slide.py", ("--runs", "1", "--arms", "baxter:right"), "false successes 0"),
    ("bench_state_entry.py", ("--rounds", "1"), "ratio, 10,000 states over 500"),
    ("count_tick.py", ("--robot", "melfa"), "melfa/main: 3845 ticks, succeeded"),
])
def test_a_simulation_benchmark_prints_its_table(script: str, args: tuple[str, ...], row: str) -> None:
    result = subprocess.run([sys.executable, str(REPO / "benchmarks" / script), *args],
                            capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, result.stderr
    assert row in result.stdout
