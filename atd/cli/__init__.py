"""The `atd` command line: the front door, above every other layer.

Each sub-command lives in its own module and registers itself on `main` (or on the
`robots` group) when imported here.
"""

from atd.cli.app import main, robots
from atd.cli import validate as _validate  # noqa: F401  (registers `atd validate`, `atd schema`)
from atd.cli import translate as _translate  # noqa: F401  (registers `atd translate`)
from atd.cli import check as _check  # noqa: F401  (registers `atd check`)
from atd.cli import robots_command as _robots  # noqa: F401  (registers `atd robots list|show`)
from atd.cli import robot_test as _robot_test  # noqa: F401  (registers `atd robots test`)
from atd.cli import robots_new as _robots_new  # noqa: F401  (registers `atd robots new`)
from atd.cli import run as _run  # noqa: F401  (registers `atd run`)
from atd.cli import graph as _graph  # noqa: F401  (registers `atd graph`)
from atd.cli import campaign_run as _campaign_run  # noqa: F401  (registers `atd campaign run`)
from atd.cli import campaign_report as _campaign_report  # noqa: F401  (registers `atd campaign report|export`)
from atd.cli import review as _review  # noqa: F401  (registers `atd report`, `atd compare`)

__all__ = ["main", "robots"]
