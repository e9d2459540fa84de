"""What every `perceive` controller shares: the container it looks in, how high it puts the
approach, and how it says what it found (an `Approach`, or `NothingFound`, in
`Context.memory` under its `writes` name, then DONE) while the arm holds still."""

from __future__ import annotations

from typing import ClassVar

from primitives.arm.move import Hold
from primitives.base import Context, ControlData, Controller, Status
from primitives.perception.container import ContainerBelief
from primitives.perception.generators import Approaching
from primitives.robot import Readings
from primitives.values import Approach, NothingFound


class Perceiver(Controller):
    """A perceive controller. Subclasses call `found` once they know; until then, and after,
    the arm holds the pose the state began with unless the subclass moves it."""

    method: ClassVar[str]

    def __init__(self, ctx: Context) -> None:
        super().__init__(ctx)
        p = self.params
        self.writes = str(p["writes"])
        self.container = ContainerBelief.from_params(p)
        self.approaching = Approaching(float(p["hand_reach"]), float(p["approach_height"]), float(p["grasp_reach"]))
        self.hold = Hold(ctx)

    def start(self, readings: Readings) -> None:
        self.ctx.memory.pop(self.writes, None)  # what an earlier round found is not what this one finds
        self.hold.start(readings)

    def found(self, approach: Approach | None, nothing: str, how: str = "") -> None:
        """Write what was found (`nothing` says why there is nothing, `how` how it was found) and finish."""
        if approach is None:
            self.ctx.memory[self.writes] = NothingFound(self.method, nothing)
            self.finish(Status.DONE, f"nothing found: {nothing}")
            return
        self.ctx.memory[self.writes] = approach
        x, y, z = approach.point
        seen = "" if approach.candidates is None else f" (one of {approach.candidates} seen)"
        self.finish(Status.DONE, f"object found{seen}: approach over ({x:.3f}, {y:.3f}, {z:.3f})"
                                 + (f" ({how})" if how else ""))

    def update(self, readings: Readings, dt: float) -> ControlData:
        return self.hold.update(readings, dt)
