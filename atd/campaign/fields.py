"""How a campaign spec's values are typed and checked: strict tables, numbers as TOML writes
them, each in its declared range. Shared by the spec and the perturbation models, so that
each model declares its own parameters without the spec knowing them."""

from __future__ import annotations

from typing import Annotated

from pydantic import AfterValidator, BaseModel, ConfigDict, Strict

from atd.model import ranges


class StrictTable(BaseModel):
    """A TOML table with only the keys its type declares, read once and never changed."""

    model_config = ConfigDict(extra="forbid", frozen=True)


# Numbers as TOML writes them: an integer may stand for a float, but `true` is not 1 and 2.0 is not a count.
Number = Annotated[float, Strict()]
Count = Annotated[int, Strict()]


def within(allowed: ranges.Range) -> AfterValidator:
    """A number checked against its declared range, in its words: NaN (TOML's `nan`) is not a
    number in any range, where pydantic's own bounds said "should be <= 0.2"."""
    def check(value: float) -> float:
        problem = allowed.problem(value)
        if problem:
            raise ValueError(problem)
        return value

    return AfterValidator(check)


def scale_range(allowed: ranges.Range) -> AfterValidator:
    """A [low, high] pair of scale factors, each in `allowed`, low not above high."""
    def check(value: tuple[float, float]) -> tuple[float, float]:
        low, high = value
        problem = allowed.first_problem(value)
        if problem or low > high:
            raise ValueError(f"give [low, high] with low <= high, each in {allowed}: {problem or f'{low:g} > {high:g}'}")
        return value

    return AfterValidator(check)


Scales = Annotated[tuple[Number, Number], scale_range(ranges.SCALE)]
# Factors that must keep a quantity above nothing: a mass, a servo's gain (no engine simulates either at 0).
PositiveScales = Annotated[tuple[Number, Number], scale_range(ranges.MASS_SCALE)]
