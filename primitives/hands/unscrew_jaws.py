"""The hand side of the unscrew on a parallel-jaw gripper (thesis 3.3.6 mapped on a gripper,
as a real one unscrews): the jaws grip the cap as the gripper's grasp grips anything
(`CloseUntilForce`: close when the arm says, centre on the pads' contacts, press with the
grasp force), keep pressing while the arm's last wrist joint twists it and the arm pulls,
and open when the arm asks, to grip again after the arm has turned back. It tells the arm
the same `CapGrip` the fingertip pinch does, so the arm side (`primitives.arm.unscrew`) is
the one the multi-finger hands use: pinched once the grip force is there, empty once the
jaws stand nearer than FINGER_MIN_DISTANCE (or, without tactile pads, at their stop),
holding while both jaws touch, and the cap's axis where the pads' contacts, averaged since
the close, put it."""

from __future__ import annotations

from enum import Enum

import numpy as np

from primitives.base import Context, ControlData, Controller, Status
from primitives.blackboard import CapGrip
from primitives.hands.extension import contact_points
from primitives.hands.parallel_jaw import CloseUntilForce, Jaws
from primitives.hands.posture import position_command
from primitives.hands.robust_grasp import GAP_CHECK
from primitives.robot import Readings


class Phase(Enum):
    """Where the jaws are; the value is the method of `UnscrewJaws` that runs a tick of it."""

    GRIP = "_grip"  # the gripper's grasp: wait for the arm's contact, close, centre, press; then keep pressing
    REOPEN = "_reopen"  # back to the opening the unscrew began with, while the arm holds still
    OFF = "_off"  # the cap is off: keep gripping it


class UnscrewJaws(Controller):
    """Grip, hold by force, report the cap to the arm, open on request: GRIP, REOPEN and
    back to GRIP; OFF once the arm says the cap came off."""

    def __init__(self, ctx: Context) -> None:
        super().__init__(ctx)
        self.min_distance = float(self.params["finger_min_distance"])
        self.jaws = Jaws(ctx, str(self.params["force_source"]))
        self.pads = list(range(len(ctx.info.hand.pads)))  # both jaws' pads; none on a gripper without them
        self.tactile = bool(self.pads) and all(pad.taxels is not None for pad in ctx.info.hand.pads)

    def start(self, readings: Readings) -> None:
        self.opened = float(readings.hand_q[0])
        self._new_grip(readings)

    def update(self, readings: Readings, dt: float) -> ControlData:
        board = self.ctx.blackboard
        if board.cap_off and self.phase is not Phase.OFF:
            self.phase = Phase.OFF
            self.finish(Status.DONE, f"holding the cap: grip force {self.jaws.force(readings):.1f} N")
        elif board.release and self.phase is Phase.GRIP:
            self.phase, self.reference = Phase.REOPEN, float(readings.hand_q[0])
            board.preshaped, board.arm_nudge = False, None
        return getattr(self, self.phase.value)(readings, dt)

    # -- phases: one tick each ------------------------------------------------------------
    def _grip(self, readings: Readings, dt: float) -> ControlData:
        command = self.grip.update(readings, dt)
        self._feel(readings)
        return command

    def _reopen(self, readings: Readings, dt: float) -> ControlData:
        """Back to the opening the unscrew began with at full speed (nothing is in the way);
        then a fresh grip waits for the arm's `contact`."""
        closing = self.jaws.closing
        self.reference -= closing * float(self.ctx.info.hand.velocity_limit[0]) * dt
        if closing * (self.reference - self.opened) <= 0.0:
            board = self.ctx.blackboard
            board.release, board.preshaped = False, True
            self._new_grip(readings)
            return position_command(np.array([self.opened]))
        return position_command(np.array([self.reference]))

    def _off(self, readings: Readings, dt: float) -> ControlData:
        return self.grip.update(readings, dt)

    # -- what the jaws say of the cap -----------------------------------------------------
    def _new_grip(self, readings: Readings) -> None:
        board = self.ctx.blackboard
        board.cap, board.jaws_empty, board.arm_nudge = CapGrip(), False, None
        self.grip = CloseUntilForce(self.ctx, rim_moves=0)  # the unscrew's arm holds still over the cap
        self.grip.start(readings)
        self.phase = Phase.GRIP
        self.contacts = np.zeros(3)  # sum of the world contact midpoints felt since the close
        self.felt = 0  # how many
        self.looked = -np.inf  # s: when the jaws' gap was last looked at

    def _feel(self, readings: Readings) -> None:
        """Pinched once the grip has its force; every GAP_CHECK (a look is the hand's forward
        kinematics), with both pads touching, add their contacts' midpoint (world frame) to
        the average that places the cap's axis; and are the jaws nearer than
        FINGER_MIN_DISTANCE with neither pad pressed (pads that both press hold something:
        the Melfa's soft pads, pressing a 40 mm cap with 10 N, stood 12 mm apart by the jaws'
        joint, MuJoCo)? Jaws without tactile pads know only their motor: closed to their stop
        they are empty, seen the tick they get there (the grip reopens them at once, between
        two looks at the pads), as the Baxter's paddles stand 26 mm apart there, over
        FINGER_MIN_DISTANCE (docs/unscrew-campaign.md); without pads, they place no axis."""
        cap = self.ctx.blackboard.cap
        cap.pinched = cap.pinched or self.grip.status is Status.DONE
        cap.holding = self.jaws.both_touch(readings, self.grip.grasp_force)
        if not self.tactile:
            cap.empty = cap.empty or self.jaws.empty(readings)
        if not self.pads:
            return
        if readings.time - self.looked < GAP_CHECK:
            return
        self.looked = readings.time
        hand = self.ctx.info.hand
        if cap.holding:
            middle = contact_points(hand, readings, self.pads).mean(axis=0)
            self.contacts += readings.tcp[:3, :3] @ middle + readings.tcp[:3, 3]
            self.felt += 1
            cap.axis = self.contacts / self.felt
        left, right = hand.pad_surfaces(readings.hand_q)[:2, :3, 3]
        cap.empty = cap.empty or (float(np.linalg.norm(left - right)) < self.min_distance and not cap.holding)
