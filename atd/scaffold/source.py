"""Python source for values that come from input (a URDF's names, paths and numbers): always
a literal, never code.

A generated package is imported by `atd robots`, `atd robots test` and pytest, so text
pasted into its source would run there. Every value from input goes through `literal`,
which writes it with `repr` and reads it back with `ast.literal_eval` before it is used;
a name that becomes Python code (an import name) goes through `identifier`.
"""

from __future__ import annotations

import ast
import keyword
import math
import re

IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]{0,63}")

_EXACT = ((int, int.__int__), (float, float.__float__), (str, str.__str__))

Value = str | int | float | bool | None | tuple["Value", ...] | dict[str, "Value"]


class SourceError(ValueError):
    """A value that cannot be written as source: it says which and why."""


def literal(value: Value) -> str:
    """`value` as a Python literal that evaluates to an equal value of the same types.

    Subclasses (a numpy float, a str subclass) are written as the built-in type they
    extend: their own repr may be code (`np.float64(0.5)`)."""
    plain = _plain(value)
    text = _render(plain)
    if not _same(ast.literal_eval(text), plain):
        raise SourceError(f"{value!r} does not read back from {text}")
    return text


def identifier(name: str) -> str:
    """`name` itself when it is a plain ASCII Python identifier (no keyword), to be written as code."""
    if not IDENTIFIER.fullmatch(name) or keyword.iskeyword(name):
        raise SourceError(f"{name!r} is not a plain Python name (letters, digits and '_', up to 64)")
    return name


def _plain(value: object) -> Value:
    """`value` made of built-in types only; SourceError for what no literal holds."""
    if value is None or isinstance(value, bool):
        return value
    for kind, exact in _EXACT:
        if isinstance(value, kind):
            plain = exact(value)  # not kind(value): a subclass may override __str__ or __float__
            if isinstance(plain, float) and not math.isfinite(plain):
                raise SourceError(f"{value!r} is not a finite number")
            return plain
    if isinstance(value, tuple):
        return tuple(_plain(item) for item in value)
    if isinstance(value, dict):
        if not all(isinstance(key, str) for key in value):
            raise SourceError(f"{value!r} has keys that are not text")
        return {str(key): _plain(item) for key, item in value.items()}
    raise SourceError(f"a {type(value).__name__} is not written as a literal")


def _render(value: Value) -> str:
    """Source for a value of built-in types only (`_plain`'s)."""
    if isinstance(value, tuple):
        items = ", ".join(_render(item) for item in value)
        return f"({items},)" if len(value) == 1 else f"({items})"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{_render(key)}: {_render(item)}" for key, item in value.items()) + "}"
    return repr(value)


def _same(read: object, value: object) -> bool:
    """Equal, and of the same types all the way down (1 is not 1.0, nor a list a tuple)."""
    if type(read) is not type(value):
        return False
    if isinstance(value, tuple):
        return len(read) == len(value) and all(_same(a, b) for a, b in zip(read, value))  # type: ignore[arg-type]
    if isinstance(value, dict):
        return list(read) == list(value) and all(_same(read[k], value[k]) for k in value)  # type: ignore[index]
    return read == value
