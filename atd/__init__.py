"""atd: describe a manipulation task once, run it on any robot.

This package holds the language (`atd.model`), the runtime and the command line. It
imports nothing at package level so that `factories` and `primitives` can depend on
`atd.model` without pulling in the runtime above them: the Python API (`from atd import run`,
atd.api, docs/api.md) is loaded on first use. It fixes one thing before numpy loads: the BLAS
kernel, so that a trial's numbers are the same on every machine (atd.blas).
"""

from atd.blas import pin_kernel

pin_kernel()

__version__ = "0.1.0"
API = ("AtdError", "RunResult", "load", "run", "run_campaign", "translate", "validate")  # not "campaign": that is the package atd.campaign
__all__ = ["API", "__version__", *API]


def __getattr__(name: str):
    if name in API:
        from atd import api

        return getattr(api, name)
    raise AttributeError(f"module 'atd' has no attribute {name!r}")
