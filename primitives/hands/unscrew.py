"""The hand side of the unscrew (thesis 3.3.6): the robust grasp's pinch (`ForceGrasp`:
close the grasping fingers, then press each pad with FINGER_GRASPING_FORCE), held through
the arm's twist and pull, closing on whenever a pad loses the cap. Each tick it tells the
arm (`Blackboard.cap`) whether the pinch has reached its force, whether the pads have
closed nearer than FINGER_MIN_DISTANCE (nothing between them), and where the pads'
contacts (a pad whose finger stopped on the cap by its link: where that pad stands),
averaged since the close, put the cap's axis (the reactive alignment, Fig. 3.12); it
opens when the arm asks (`release`). Phases: `primitives.hands.grasp_phases`."""

from __future__ import annotations

import numpy as np

from primitives.base import Context, ControlData, Status
from primitives.blackboard import CapGrip
from primitives.filters import LowPass
from primitives.hands.extension import ExtensionGauge, contact_points, pad_corners
from primitives.hands.force_grasp import ForceGrasp
from primitives.hands.grasp_phases import Phase
from primitives.hands.multi_finger import CLOSING_SPEED
from primitives.hands.robust_grasp import FELT_TIME, GAP_CHECK, HELD, OPENING_SPEED, SETTLE_TIME
from primitives.robot import Readings


class UnscrewHand(ForceGrasp):
    """Pinch, hold by force, report the cap to the arm, open on request: PRESHAPE, WAIT,
    CLOSE, HOLD, REOPEN and back to WAIT."""

    def __init__(self, ctx: Context) -> None:
        super().__init__(ctx)
        self.min_distance = float(self.params["finger_min_distance"])
        reach, width = self.params.get("pad_reach"), self.params.get("cap_width")
        # (pad_reach, cap_width): where the pads' lower edge stands at the believed width; None: not followed
        self.believed = None if reach is None or width is None else (float(reach), float(width))

    def start(self, readings: Readings) -> None:
        super().start(readings)
        self.ctx.blackboard.cap = CapGrip()
        self.pads = [self.pad_of[f] for f in self.fingers]
        self.squaring = self._squaring()
        if self.fingers:
            self.gauge = ExtensionGauge(self.ctx.info.hand, self.pads, self.pre)
        self._new_pinch()

    def update(self, readings: Readings, dt: float) -> ControlData:
        board = self.ctx.blackboard
        if board.release and self.phase not in (Phase.REOPEN, Phase.FAILED):
            self.phase, self.effort[:] = Phase.REOPEN, 0.0
            self.stillness.seconds[:] = 0.0
            board.preshaped = False
        if board.cap_off:
            self.finish(Status.DONE, f"holding the cap: {self._forces(readings)}")
        return super().update(readings, dt)

    # -- phases: one tick each ------------------------------------------------------------
    def _close(self, readings: Readings, dt: float) -> None:
        """Close until the fingers stop or every grasping pad presses the grasp force; then hold."""
        self._square(self.reference)
        self._feel(readings)
        self._follow(readings)
        pressed = all(readings.pad_force[k] >= self.grasp_force for k in self.pads)
        if self._closed(readings, dt) or pressed:
            self.ctx.blackboard.fingers_stopped = True
            self.effort = self._starting_effort(readings)
            self.phase = Phase.HOLD

    def _hold(self, readings: Readings, dt: float) -> None:
        """Force adaptation; pinched once every grasping pad, its force averaged over
        FELT_TIME as the robust grasp judges its hold, has felt the grasp force (within
        1 - HELD) for SETTLE_TIME: a squeeze at the grasp force reads in ticks under it
        where the pads' contacts chatter (a Barrett's pinch in PyBullet, each pad 8.7-12 N
        tick to tick about 10 N, docs/unscrew-campaign.md)."""
        felt = self.squeeze(self._adapt(readings, dt), dt)
        self._square(readings.hand_q)
        self._feel(readings)
        self.pressed_for = self.pressed_for + dt if bool((felt >= HELD * self.grasp_force).all()) else 0.0
        cap = self.ctx.blackboard.cap
        cap.pinched = cap.pinched or self.pressed_for >= SETTLE_TIME

    def _reopen(self, readings: Readings, dt: float) -> None:
        """Back to the preshape, fast; then a fresh pinch waits for the arm's `contact`."""
        if self._ramp(self.pre, dt, readings.hand_q, OPENING_SPEED / CLOSING_SPEED) or self._blocked(readings, dt):
            board = self.ctx.blackboard
            self.phase, board.release, board.preshaped = Phase.WAIT, False, True
            self._new_pinch()

    # -- keeping the pads square to the cap -----------------------------------------------
    def _squaring(self) -> list[tuple[int, int, float]]:
        """(closing DOF, follower, sign) for each grasping finger with a second DOF of its own
        that the grasp does not close: a pad on a two-joint finger turns with both."""
        hand = self.ctx.info.hand
        pairs = []
        for i in np.flatnonzero(self.moving):
            pad = hand.pads[self.pad_of[f]] if (f := self.finger_of_dof[i]) else None
            own = [k for k in (pad.dofs if pad else ()) if k != i and self.finger_of_dof[k] == f and not self.moving[k]]
            pairs += [(int(i), k, float(hand.closing[k] * hand.closing[i])) for k in own if hand.closing[k]]
        return pairs

    def _square(self, closing: np.ndarray) -> None:
        """Flex each follower back by what its finger's closing DOF has closed (`closing`:
        where that DOF is, or is sent), so the pad keeps the slant it had in the preshape,
        square to the pinch line: pads that closed at a slant met the cap with the bare
        fingertips below them (the SDH2 on the jam jar, MuJoCo: 10 N on the link beside the
        neck, 2 N on the pad, never the grasp force)."""
        self.reference = self._squared(closing, self.reference)

    def _squared(self, closing: np.ndarray, posture: np.ndarray) -> np.ndarray:
        """`posture` with each follower where squaring puts it for the closing DOFs at `closing`."""
        posture = posture.copy()
        for i, k, sign in self.squaring:
            posture[k] = self.pre[k] - sign * (closing[i] - self.pre[i])
        return posture

    def _follow(self, readings: Readings) -> None:
        """Once the pads have closed nearer than the cap's believed width, ask the arm down
        by how far their lower edge has risen over where it stands at that width
        (`pad_reach`, where the arm put it), so that they pinch as deep as the task asked on
        a narrower cap too: a Barrett's curling fingers closing from 60 mm to a 30 mm cap
        lift their pads' tips 14 mm, over its top. Only ever further down. The pads as
        squaring holds them (a follower's servo lag tilted the SDH2's and read as a rise)."""
        if self.believed is None or not self.fingers:
            return
        reach, width = self.believed
        if self.gauge.gap(readings.hand_q) > width:
            return
        posture = self._squared(readings.hand_q, readings.hand_q)
        edge = float(pad_corners(self.ctx.info.hand, posture, self.pads)[:, :, 2].max())
        cap = self.ctx.blackboard.cap
        cap.drop = max(cap.drop, reach - edge)

    # -- what the pads say of the cap -----------------------------------------------------
    def _new_pinch(self) -> None:
        self.ctx.blackboard.cap = CapGrip()
        self.pressed_for = 0.0
        self.squeeze = LowPass(FELT_TIME)  # the grasping pads' forces through the hold, from its first tick
        self.contacts = np.zeros(3)  # sum of the world contact midpoints felt since the close
        self.felt = 0  # how many
        self.looked = -np.inf  # s: when the pads' gap was last looked at

    def _feel(self, readings: Readings) -> None:
        """Every GAP_CHECK (a look is the hand's forward kinematics): with every grasping
        finger on the cap (`_on_cap`), add their pads' midpoint (world frame) to the average
        that places the cap's axis; and are the pads nearer than FINGER_MIN_DISTANCE?"""
        cap = self.ctx.blackboard.cap
        cap.holding = len(self._touching(readings)) == len(self.fingers)
        if readings.time - self.looked < GAP_CHECK:
            return
        self.looked = readings.time
        if self._on_cap(readings, cap):
            middle = contact_points(self.ctx.info.hand, readings, self.pads).mean(axis=0)
            self.contacts += readings.tcp[:3, :3] @ middle + readings.tcp[:3, 3]
            self.felt += 1
            cap.axis = self.contacts / self.felt
        cap.empty = cap.empty or self.gauge.gap(readings.hand_q) < self.min_distance

    def _on_cap(self, readings: Readings, cap: CapGrip) -> bool:
        """Every grasping pad touches (`holding`); or, the close over and the pinch not yet
        pressed (a pad that slips later has a finger closing on, not stopped), some pad
        presses and each finger whose pad feels nothing stopped short of closed, on the cap
        by its bare link (a Barrett's finger on the side the hand came down off towards
        curls over the cap's rim, its pad past it, docs/unscrew-campaign.md). That pad's
        centre stands beyond the cap's side, so the midpoint errs towards its finger, but it
        lies towards the axis from where the hand pinched: the next pinch, nearer, presses
        both pads."""
        if cap.holding:
            return True
        touching = self._touching(readings)
        if self.phase is not Phase.HOLD or cap.pinched or not touching:
            return False
        short = ~self._at_closed(readings.hand_q)
        return all(short[i] for i in np.flatnonzero(self.moving) if self.finger_of_dof[i] not in touching)

    def _forces(self, readings: Readings) -> str:
        return ", ".join(f"{f} {readings.pad_force[self.pad_of[f]]:.1f} N" for f in self.fingers)
