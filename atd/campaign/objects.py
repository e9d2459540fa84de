"""The object library, which now lives in the simulator (`atd.sim.library`): campaigns keep
importing it from here."""

from atd.sim.library import LibraryObject, UnknownObject, get, library, mesh_file

__all__ = ["LibraryObject", "UnknownObject", "get", "library", "mesh_file"]
