"""Diagnostics are data: a stable code, a severity, a place, a message and a hint.

Every stage (reading, validating, translating) reports through these, so the command
line can print them like a compiler or as JSON, and tests can assert on codes and lines.
"""

from __future__ import annotations

import difflib
import json
from dataclasses import asdict, dataclass
from enum import StrEnum
from typing import Iterable

from atd.model.task import Location


class Severity(StrEnum):
    ERROR = "error"
    WARNING = "warning"


@dataclass(frozen=True)
class Diagnostic:
    code: str
    severity: Severity
    message: str
    loc: Location | None = None
    hint: str | None = None

    def render(self) -> str:
        where = f"{self.loc}: " if self.loc else ""
        text = f"{where}{self.severity.value}[{self.code}]: {self.message}"
        return f"{text}\n  hint: {self.hint}" if self.hint else text

    def as_dict(self) -> dict:
        d = asdict(self)
        d["severity"] = self.severity.value
        d["loc"] = asdict(self.loc) if self.loc else None
        return d


def error(code: str, message: str, loc: Location | None = None, hint: str | None = None) -> Diagnostic:
    return Diagnostic(code, Severity.ERROR, message, loc, hint)


def warning(code: str, message: str, loc: Location | None = None, hint: str | None = None) -> Diagnostic:
    return Diagnostic(code, Severity.WARNING, message, loc, hint)


def has_errors(diagnostics: Iterable[Diagnostic]) -> bool:
    return any(d.severity is Severity.ERROR for d in diagnostics)


def did_you_mean(word: str, choices: Iterable[str]) -> str | None:
    """A hint naming the closest known word, as compilers do for misspellings."""
    close = difflib.get_close_matches(word, list(choices), n=1, cutoff=0.6)
    return f"did you mean '{close[0]}'?" if close else None


def sort_key(d: Diagnostic) -> tuple:
    loc = d.loc or Location("", 0, 0)
    return (loc.file, loc.line, loc.col, d.code)


def render_all(diagnostics: list[Diagnostic]) -> str:
    """Compiler-style text, in file order, with a closing count."""
    lines = [d.render() for d in sorted(diagnostics, key=sort_key)]
    errors = sum(d.severity is Severity.ERROR for d in diagnostics)
    warnings = len(diagnostics) - errors
    lines.append(f"{errors} error{'s' * (errors != 1)}, {warnings} warning{'s' * (warnings != 1)}")
    return "\n".join(lines)


def to_json(diagnostics: list[Diagnostic]) -> str:
    return json.dumps([d.as_dict() for d in sorted(diagnostics, key=sort_key)], indent=2)
