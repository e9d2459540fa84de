"""The fingertip pinch that the robust grasp and the unscrew share: close the grasping
fingers, then press each pad with a grasp force by force adaptation (thesis 3.3.1,
3.3.6: "closes the selected fingers until FINGER_GRASPING_FORCE is achieved on each
fingertip"). Subclasses say when to close, how to judge a close and what to hold for."""

from __future__ import annotations

import numpy as np

from primitives.base import Context
from primitives.hands.multi_finger import FingerGrasp
from primitives.robot import Readings

TOUCH_EFFORT = 0.05  # of the effort limit: a light touch, the least force adaptation starts from
ADAPT_GAIN = 0.05  # effort (fraction of the limit) per N of missing pad force, per s


class ForceGrasp(FingerGrasp):
    """A multi-finger grasp that holds by pressing each grasping pad with `grasp_force`."""

    def __init__(self, ctx: Context) -> None:
        super().__init__(ctx)
        self.grasp_force = float(self.params["grasp_force"])

    def _starting_effort(self, readings: Readings) -> np.ndarray:
        """Where force adaptation starts: at rest a pad's force grows with the effort behind
        it, so each stopped finger's effort scaled to the grasp force is close to the one
        that holds it; from a light touch the integrator took seconds to climb back. Every
        finger starts from the least of these: opposed fingers pressing unequally push the
        object aside."""
        hand = self.ctx.info.hand
        pads, pressed = readings.pad_force, np.maximum(0.0, hand.closing * readings.hand_effort)
        touch = TOUCH_EFFORT * hand.effort_limit
        scaled = [pressed[i] * self.grasp_force / pads[self.pad_of[f]] / hand.effort_limit[i]
                  for i in np.flatnonzero(self.moving)
                  if (f := self.finger_of_dof[i]) and pads[self.pad_of[f]] >= self.touch]
        share = min(scaled, default=0.0)  # of each DOF's effort limit
        return np.where(self.moving, np.clip(share * hand.effort_limit, touch, hand.effort_limit), 0.0)

    def _strongest(self) -> bool:
        """Every grasping finger presses with all its effort: the pads feel what this hand
        can give the object, though short of the grasp force where the links beside the pads
        carry some of the squeeze (an SDH2 around the bunny's body: pads 2-3 N of 5 N)."""
        limit = self.ctx.info.hand.effort_limit
        return bool((self.effort[self.moving] >= limit[self.moving]).all())

    def _adapt(self, readings: Readings, dt: float) -> np.ndarray:
        """One tick of force adaptation: each grasping finger's effort rises until its pad
        feels the grasp force; the two fingers of a pinch share one squeeze, driven by their
        pads' mean (each finger's own loop pushed the object along the pinch line). A finger
        whose pad lost the object closes on until it feels it again. Returns the grasping
        DOFs' pad forces."""
        hand = self.ctx.info.hand
        pads = readings.pad_force
        grasping = np.flatnonzero(self.moving)
        felt = np.array([pads[self.pad_of[f]] if (f := self.finger_of_dof[i]) else self.grasp_force for i in grasping])
        pressed = np.full_like(felt, felt.mean()) if self.pinch else felt
        limit = hand.effort_limit[grasping]
        self.effort[grasping] = np.clip(self.effort[grasping] + ADAPT_GAIN * limit * (self.grasp_force - pressed) * dt,
                                        0.0, limit)
        return felt
