"""The `atd` command line: the front door, above every other layer.

Each sub-command lives in its own module and registers itself on `main` (or on the
`robots` or `campaign` group); `atd.cli.app` names that module for each command and
imports it when the command is used.
"""

from atd.cli.app import main, robots

__all__ = ["main", "robots"]
