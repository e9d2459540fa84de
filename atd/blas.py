"""One BLAS kernel on every x86-64 machine, so that a trial's record does not depend on its CPU.

OpenBLAS picks its kernel when it loads: Haswell's on a CPU with AVX2, SkylakeX's on one with
AVX-512. The two sum a dot product in different orders, a joint command differs in its last
bit, and a simulated grasp that hangs on one contact can end the other way: three pinned preset
trials of the test suite do (docs/reliability.md). Haswell's kernel runs on every x86-64 CPU with
AVX2 and FMA, so `atd` asks for it there, before numpy loads OpenBLAS; campaign workers inherit
the choice with the environment. A user's own OPENBLAS_CORETYPE is kept.
"""

from __future__ import annotations

import os
import platform
from pathlib import Path

KERNEL = "Haswell"
_NEEDS = {"avx2", "fma"}  # what Haswell's kernel executes


def pin_kernel() -> None:
    """Ask OpenBLAS for `KERNEL` where the CPU runs it, unless the user chose one."""
    if "OPENBLAS_CORETYPE" not in os.environ and _cpu_runs_kernel():
        os.environ["OPENBLAS_CORETYPE"] = KERNEL


def _cpu_runs_kernel() -> bool:
    if platform.machine().lower() not in ("x86_64", "amd64"):
        return False
    try:
        lines = Path("/proc/cpuinfo").read_text().splitlines()
    except OSError:  # not Linux: OpenBLAS chooses as it does
        return False
    flags = next((line.partition(":")[2].split() for line in lines if line.startswith("flags")), [])
    return _NEEDS <= set(flags)
