"""The base of every immutable model: equal by value, and safe to copy with changes.

A model may cache indexes derived from its fields (`functools.cached_property`); pydantic's
`model_copy(update=...)` copies those caches along with the fields, so a copy with new
states would keep answering from the old ones. Copies here start without them.
"""

from __future__ import annotations

from functools import cache, cached_property
from typing import Any

from pydantic import BaseModel, ConfigDict


@cache
def _cached_names(cls: type) -> tuple[str, ...]:
    return tuple(name for klass in cls.__mro__ for name, value in vars(klass).items()
                 if isinstance(value, cached_property))


class Frozen(BaseModel):
    model_config = ConfigDict(frozen=True, extra="forbid")

    def model_copy(self, *, update: dict[str, Any] | None = None, deep: bool = False):  # type: ignore[override]
        copy = super().model_copy(update=update, deep=deep)
        for name in _cached_names(type(self)):
            copy.__dict__.pop(name, None)
        return copy
