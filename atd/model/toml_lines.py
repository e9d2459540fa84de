"""Where each key of a TOML text stands, for errors that point at a line.

Python's TOML reader keeps no positions; campaign specs and robot configs both need them.
"""

from __future__ import annotations

import re

from atd.model.task import Location


class TomlLines:
    """Where each key of a TOML text stands: enough of TOML's grammar to point a
    diagnostic at the line of a key, a table or an array-of-tables entry."""

    _HEADER = re.compile(r"^\s*(\[\[?)\s*([^\]]+?)\s*\]\]?")
    _KEY = re.compile(r"^\s*([A-Za-z0-9_\-\"'.]+)\s*=")

    def __init__(self, text: str) -> None:
        self.lines: dict[tuple, int] = {}
        counts: dict[tuple, int] = {}
        table: tuple = ()
        for number, line in enumerate(text.splitlines(), start=1):
            if m := self._HEADER.match(line):
                path = tuple(p.strip().strip("\"'") for p in m.group(2).split("."))
                if m.group(1) == "[[":
                    index = counts.get(path, 0)
                    counts[path] = index + 1
                    path = path + (index,)
                table = path
                self.lines.setdefault(table, number)
            elif m := self._KEY.match(line):
                key = tuple(p.strip().strip("\"'") for p in m.group(1).split("."))
                self.lines.setdefault(table + key, number)

    def find(self, loc: tuple, where: str) -> Location:
        """The line of `loc`, or of its nearest enclosing key or table."""
        path = tuple(loc)
        while path:
            if path in self.lines:
                return Location(where, self.lines[path])
            path = path[:-1]
        return Location(where, 1)
