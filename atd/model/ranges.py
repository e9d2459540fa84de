"""The allowed range of every number a user can give: in an ATD, in a robot config, on the
command line. Declared here once, and checked by `Range.problem` wherever a number is read.

A NaN passes every comparison and an infinity outruns every limit, so a number that is not
finite is never in range. The bounds are what the controllers and the engines can act on
sensibly: a speed limit of 0 would be no limit, a mass of a microgram makes MuJoCo fail.
"""

from __future__ import annotations

import itertools
import math
import re
from dataclasses import dataclass


@dataclass(frozen=True)
class Range:
    """A closed or half-open interval of finite numbers, with its unit for messages."""

    low: float
    high: float
    unit: str = ""
    low_open: bool = False

    def __str__(self) -> str:
        text = f"{'(' if self.low_open else '['}{_number(self.low)}, {_number(self.high)}]"
        return f"{text} {self.unit}" if self.unit else text

    def problem(self, value: float) -> str | None:
        """Why `value` is refused, in words naming the allowed range; None when it is allowed.
        An integer is compared as it is: one of 400 digits overflows a float."""
        if not isinstance(value, int) and not math.isfinite(value):
            return f"{value} is not a finite number; give one in {self}"
        if value < self.low or value > self.high or (self.low_open and value == self.low):
            return f"{_number(value)} is outside {self}"
        return None

    def first_problem(self, values: tuple[float, ...]) -> str | None:
        """`problem` of the first value refused; None when all are allowed. Tried whole first
        (a task holds hundreds of thousands of numbers, nearly all in range)."""
        if values and all(map(math.isfinite, values)):
            lowest = min(values)
            if self.low <= lowest and max(values) <= self.high and not (self.low_open and lowest == self.low):
                return None
        return next(filter(None, map(self.problem, values)), None)


# A number as a person writes it in a file or on a command line: ASCII digits, a point, an
# exponent; the words for infinity and NaN too, so that they are refused as not finite. Python's
# float() and int() would also take '1_000' and other scripts' digits ('١٢'), which no XML
# schema, TOML file or other tool reads as numbers.
_NUMBER = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?|[+-]?(?:inf|infinity|nan)",
                     re.IGNORECASE)
_INTEGER = re.compile(r"[+-]?[0-9]+")


def numbers(words: list[str]) -> tuple[float, ...]:
    """The numbers written as `words`; ValueError naming the first word that is not one."""
    bad = next(itertools.filterfalse(_NUMBER.fullmatch, words), None)
    if bad is not None:
        raise ValueError(f"'{bad}' is not a number")
    return tuple(map(float, words))


def integer(word: str) -> int:
    """The whole number written as `word`; ValueError when it is not one."""
    if not _INTEGER.fullmatch(word.strip()):
        raise ValueError(f"'{word.strip()}' is not an integer")
    return int(word)


def _number(value: float) -> str:
    """A number as a message shows it: a whole one in digits (a seed of 4294967296, not 4.29497e+09),
    up to 20 of them; any other as %g."""
    if isinstance(value, int):
        digits = str(value)
        return digits if len(digits) <= 20 else f"{digits[:10]}... ({len(digits)} digits)"
    return str(int(value)) if value.is_integer() and abs(value) < 1e15 else f"{value:g}"


# ATD values: the object, the world, the task's timing.
COORDINATE = Range(-10.0, 10.0, "m")  # positions, targets, waypoints: a robot's workspace and then some
# Object and obstacle dimensions (a wall is an obstacle too). A millimetre at least: MuJoCo refuses
# the model of a smaller object (its inertia falls below mjMINVAL), 1e-9 m crashed `atd run`.
SIZE = Range(0.001, 10.0, "m")
SIZE_OR_NONE = Range(0.0, 10.0, "m")  # a size a controller may be given: 0 is none
OBSTACLE_EXTENT = Range(0.0, 10.0, "m")  # in an ESTD: 0 0 0 is an obstacle of no given size
WEIGHT = Range(0.001, 50.0, "kg")  # what both engines simulate stably next to a robot hand
INERTIA = Range(-10.0, 10.0, "kg m^2")
FRICTION = Range(0.0, 10.0)
TIMEOUT = Range(0.0, 86_400.0, "s", low_open=True)  # a day
FRACTION = Range(0.0, 1.0)
CLEARANCE = Range(0.0, 0.1, "m")  # a world's objects laid this far from a box's walls: past 10 cm none fits

# Controller and condition parameters, by the quantity they are (see atd.model.controllers).
SPEED = Range(0.0, 2.0, "m/s", low_open=True)
FORCE = Range(0.0, 1000.0, "N", low_open=True)
TORQUE = Range(0.0, 100.0, "N m", low_open=True)
DISTANCE = Range(0.0, 5.0, "m", low_open=True)
DURATION = Range(0.0, 60.0, "s")  # filters and dwell times; 0 means none
SPEED_FRACTION = Range(0.0, 1.0, low_open=True)  # of a joint's speed limit; 0 would never move
TRAVEL_RATE = Range(0.0, 10.0, "1/s", low_open=True)  # a fraction of a joint's travel per second
LIMITS = Range(0.0, 100.0)  # velocity and acceleration limits; 0 means none
DIRECTION = Range(-1.0, 1.0)  # components of a direction or normal
PADS = Range(1, 64)
COUNT = Range(0, 1000)  # how many times a primitive may try something: corrections, search points
ANGLE = Range(0.0, 90.0, "deg")  # an angle from a direction, as a tolerance
TILT = Range(-180.0, 180.0, "deg")  # the hand turned away from top-down, about each world axis (rpy)
YAW = Range(-180.0, 180.0, "deg")  # the hand's heading about the world vertical

CONTACT_MARGIN = Range(-1.0, 5.0, "m")  # negative: any contact ends a guarded move

BY_UNIT = {"m/s": SPEED, "N": FORCE, "N m": TORQUE, "m": DISTANCE, "s": DURATION, "": FRACTION, "kg": WEIGHT,
           "1/s": TRAVEL_RATE}

# Command line.
BUDGET = Range(0.0, 86_400.0, "s", low_open=True)
SEED = Range(0, 2**32 - 1)  # numpy's seed range
RECORD_RATE = Range(0.0, 10_000.0, "Hz", low_open=True)  # of simulated time; a tick is 200-1000 Hz
WORKERS = Range(1, 512)  # campaign worker processes, each holding an engine: more only exhausts memory
TRIALS = Range(1, 100_000)  # per cell, in a campaign spec or --trials
SCALE = Range(0.0, 100.0)  # a campaign's perturbation factors (friction, sensor noise and bias)
MASS_SCALE = Range(0.01, 100.0)  # of no mass, or a 1 g object scaled far below a gram, no engine can simulate
