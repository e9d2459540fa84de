"""Diagnostics are data: a stable code, a severity, a place, a message and a hint.

Every stage (reading, validating, translating) reports through these, so the command
line can print them like a compiler or as JSON, and tests can assert on codes and lines.
"""

from __future__ import annotations

import difflib
import json
import re
from collections import defaultdict
from dataclasses import asdict, dataclass
from enum import StrEnum
from typing import Iterable

from atd.model.task import Location


class Severity(StrEnum):
    ERROR = "error"
    WARNING = "warning"


LONGEST_TEXT = 2_000  # characters of a message or hint; only one repeating a huge input is longer
_LONG_WORD = re.compile(r"[^\s'\"]{101,}")


def _shortened(text: str | None) -> str | None:
    """`text`, or when it repeats a huge piece of the input (a state name of ten million
    characters) its long words cut to their start and length, and the whole to LONGEST_TEXT:
    a diagnostic stays a line to read, not megabytes."""
    if text is None or len(text) <= LONGEST_TEXT:
        return text
    text = _LONG_WORD.sub(lambda m: f"{m.group()[:40]}... ({len(m.group()):,} characters)", text)
    return text if len(text) <= LONGEST_TEXT else f"{text[:LONGEST_TEXT]}... ({len(text):,} characters in all)"


@dataclass(frozen=True)
class Diagnostic:
    code: str
    severity: Severity
    message: str
    loc: Location | None = None
    hint: str | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "message", _shortened(self.message))
        object.__setattr__(self, "hint", _shortened(self.hint))

    def render(self) -> str:
        where = f"{self.loc}: " if self.loc else ""
        text = f"{where}{self.severity.value}[{self.code}]: {self.message}"
        return f"{text}\n  hint: {self.hint}" if self.hint else text

    def as_dict(self) -> dict:
        d = asdict(self)
        d["severity"] = self.severity.value
        d["loc"] = self.loc._asdict() if self.loc else None
        return d


def error(code: str, message: str, loc: Location | None = None, hint: str | None = None) -> Diagnostic:
    return Diagnostic(code, Severity.ERROR, message, loc, hint)


def warning(code: str, message: str, loc: Location | None = None, hint: str | None = None) -> Diagnostic:
    return Diagnostic(code, Severity.WARNING, message, loc, hint)


def has_errors(diagnostics: Iterable[Diagnostic]) -> bool:
    return any(d.severity is Severity.ERROR for d in diagnostics)


class Suggester:
    """"Did you mean" hints for many misspellings among many names, each in time that does
    not grow with the number of names.

    Small vocabularies are searched whole. Large ones (a task's state names) are indexed by
    every one-letter deletion of each name; a word is looked up by its deletions of up to two
    letters (one for long words). That finds any name one edit away (a letter dropped,
    added, changed or two swapped) and most two away; only those candidates are ranked.
    """

    SMALL = 200  # names searched whole
    LONGEST = 64  # longer names are indexed as they are, not by their deletions
    TWO_EDITS = 24  # words up to this long are also looked up by their two-letter deletions
    PER_KEY = 32  # candidates kept per deletion key: hints, not an exhaustive search

    def __init__(self, choices: Iterable[str]) -> None:
        self.choices = list(dict.fromkeys(choices))
        self.index: dict[str, list[str]] | None = None
        if len(self.choices) > self.SMALL:
            self.index = defaultdict(list)
            for name in self.choices:
                for key in _deletions(name):
                    if len(self.index[key]) < self.PER_KEY:
                        self.index[key].append(name)

    def hint(self, word: str) -> str | None:
        """A hint naming the closest known word, as compilers do for misspellings."""
        if self.index is None:
            pool = self.choices
        else:
            keys = _deletions(word)
            if len(word) <= self.TWO_EDITS:
                keys = {k2 for k in keys for k2 in _deletions(k)}
            pool = list(dict.fromkeys(n for key in keys for n in self.index.get(key, ())))
        close = difflib.get_close_matches(word, pool, n=1, cutoff=0.6)
        return f"did you mean '{close[0]}'?" if close else None


def _deletions(word: str) -> set[str]:
    if len(word) > Suggester.LONGEST:
        return {word}
    return {word} | {word[:i] + word[i + 1:] for i in range(len(word))}


def did_you_mean(word: str, choices: Iterable[str]) -> str | None:
    """A hint naming the closest known word, as compilers do for misspellings."""
    return Suggester(choices).hint(word)


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
