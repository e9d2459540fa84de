"""atd: describe a manipulation task once, run it on any robot.

This package holds the language (`atd.model`), the runtime and the command line. It
imports nothing at package level so that `factories` and `primitives` can depend on
`atd.model` without pulling in the runtime above them.
"""

__version__ = "0.1.0"
