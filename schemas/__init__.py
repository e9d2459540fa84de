"""The published file formats: XSDs for ATD and ESTD files, JSON Schemas of their models.

A package (not a bare folder) so the schemas ship inside the installed distribution and
`importlib.resources` finds them whether `atd` was installed editable or not.
"""

from importlib.resources import files
from pathlib import Path


def schema_path(name: str) -> Path:
    """Path of a schema file shipped with this package, e.g. ``schema_path("atd.xsd")``."""
    return Path(str(files(__name__) / name))
