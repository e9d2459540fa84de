"""Importing atd fixes OpenBLAS's kernel, so a trial's record is the same on every x86-64 CPU
with AVX2 (atd.blas): without it, three pinned preset trials ended the other way on a CPU
with AVX-512."""

from __future__ import annotations

import os
import platform
import subprocess
import sys
from pathlib import Path

# A dot product whose last bit depends on the order the kernel sums in.
_DOT = "import numpy as np; r = np.random.default_rng(7); print(repr(float(r.normal(size=37) @ r.normal(size=37))))"


def _python(code: str, **env: str) -> str:
    clean = {k: v for k, v in os.environ.items() if k != "OPENBLAS_CORETYPE"} | env
    return subprocess.run([sys.executable, "-c", code], env=clean, capture_output=True, text=True, check=True).stdout


def _avx2_linux() -> bool:
    cpuinfo = Path("/proc/cpuinfo")
    return (platform.machine() == "x86_64" and cpuinfo.exists()
            and {"avx2", "fma"} <= set(cpuinfo.read_text().partition("flags")[2].partition("\n")[0].split()))


def test_importing_atd_asks_openblas_for_one_kernel_before_numpy_loads_it() -> None:
    kernel = _python("import atd, os; print(os.environ.get('OPENBLAS_CORETYPE'))").strip()
    assert kernel == ("Haswell" if _avx2_linux() else "None")
    assert _python(f"import atd; {_DOT}") == _python(_DOT, OPENBLAS_CORETYPE=kernel if _avx2_linux() else "")


def test_a_users_own_kernel_is_kept() -> None:
    assert _python("import atd, os; print(os.environ['OPENBLAS_CORETYPE'])", OPENBLAS_CORETYPE="Prescott").strip() == "Prescott"
