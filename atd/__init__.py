"""atd: describe a manipulation task once, run it on any robot.

This package holds the language (`atd.model`), the runtime and the command line. It
imports nothing at package level so that `factories` and `primitives` can depend on
`atd.model` without pulling in the runtime above them. It fixes one thing before numpy loads:
the BLAS kernel, so that a trial's numbers are the same on every machine (atd.blas).
"""

from atd.blas import pin_kernel

pin_kernel()

__version__ = "0.1.0"
