"""Turning the hand in place: blind exploration turns it between its legs, where a hand
wider one way than the other comes nearer a wall with its narrow side towards it."""

from __future__ import annotations

import numpy as np

from primitives.arm.explore import ARRIVED
from primitives.arm.motion import GAIN, ORIENTATION_TOLERANCE, STALL_TIME, Stall, orientation_twist, what_stops
from primitives.arm.move import arm_output
from primitives.base import Context, ControlData, Controller, Status
from primitives.robot import Readings


class Turn(Controller):
    """Turn the hand to `goal` (3x3, world) where it stands, holding the TCP there: DONE within
    ORIENTATION_TOLERANCE; no nearer it for STALL_TIME (`Stall`: a joint at its limit), ERROR,
    `blocked`. Read as an explore move that met nothing (`found` None, `rest` where it stands)."""

    def __init__(self, ctx: Context, goal: np.ndarray) -> None:
        super().__init__(ctx)
        self.goal = np.asarray(goal, float)
        self.stall = Stall()
        self.found = None
        self.blocked = False

    def start(self, readings: Readings) -> None:
        self.rest = readings.tcp[:3, 3].copy()
        self.stall.reset(readings.time)

    def update(self, readings: Readings, dt: float) -> ControlData:
        w, angle = orientation_twist(self.goal, readings.tcp[:3, :3])
        held = GAIN * (self.rest - readings.tcp[:3, 3])
        if self.status is Status.RUNNING:
            if angle < ORIENTATION_TOLERANCE and float(np.linalg.norm(held)) < GAIN * ARRIVED:
                self.finish(Status.DONE, f"turned ({np.degrees(angle):.1f} deg off)")
            elif self.stall.stalled(0.0, readings.time, angle):
                self.blocked = True
                info = self.ctx.info
                stops = what_stops(readings.arm_q, info.arm_joints, info.arm_lower, info.arm_upper)
                self.finish(Status.ERROR, f"the turn made no progress for {STALL_TIME:g} s, "
                                          f"{np.degrees(angle):.0f} deg short: {stops}")
        return arm_output(np.concatenate([held, w]))  # done, it holds the turn as the legs after it will
