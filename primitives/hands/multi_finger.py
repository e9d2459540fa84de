"""Grasps of multi-finger hands: what every one shares (`FingerGrasp`: its phases preshape,
wait for the arm, close, hold), and the naive baseline grasp of thesis 3.4.1. The robust
grasp (thesis 3.3.1, D5 appendix) builds on it in `primitives.hands.robust_grasp`.

Where each finger stands on the palm (`PadInfo.base`, from the robot's description) and
which DOFs move it is all a grasp needs to know of the hand.
"""

from __future__ import annotations

from abc import abstractmethod

import numpy as np

from primitives.base import Context, ControlData, Controller, HandCommand, Status
from primitives.blackboard import EMPTY_HAND
from primitives.filters import world_load
from primitives.hands.grasp_phases import Phase
from primitives.hands.posture import Stillness
from primitives.robot import HandMode, Readings

CLOSING_SPEED = 0.3  # of each DOF's speed limit: slow enough that a finger stops on what it meets
LEAD = 0.05  # of a DOF's range a closing finger's reference may run ahead of it: a blocked finger's push stays bounded
STALL_TIME = 0.3  # s a finger may stand still before it counts as stopped: longer than a pause on a fingertip's slide
REACHED = 0.02  # of a DOF's range: a DOF this near its goal or limit has reached it


class FingerGrasp(Controller):
    """What every grasp of a multi-finger hand shares: which DOFs grasp (those the grasp
    posture moves), which pad each one's finger carries, and the phases preshape, wait
    for the arm's `contact`, close, and hold (`Phase`, a method each); subclasses say how
    to close and how to hold."""

    def __init__(self, ctx: Context) -> None:
        super().__init__(ctx)
        hand = ctx.info.hand
        postures = hand.postures
        shapes = [s for s in (self.params.get("preshape"), self.params.get("grasp_shape")) if s is not None]
        for shape in shapes:
            if shape not in postures:
                raise ValueError(f"the hand cannot make the shape '{shape}'; it makes: {', '.join(sorted(postures))}")
        if self.params.get("grasp_shape") is None:
            raise ValueError("a multi-finger grasp needs grasp_shape")
        self.grasp = np.asarray(postures[self.params["grasp_shape"]], float)
        self.preshape = np.asarray(postures[self.params["preshape"]], float) if self.params.get("preshape") else None
        self.size = self.params.get("pregrasp_size")
        self.touch = float(self.params["contact_threshold"])
        self.range = hand.upper - hand.lower
        self.rate = CLOSING_SPEED * hand.velocity_limit
        self.slowed = 1.0  # of `rate` the grasping fingers close at
        self.stillness = Stillness(hand.velocity_limit, STALL_TIME)
        # A finger is known by its pad; a DOF belongs to the one finger whose pad it moves
        # (a spread that moves two fingers, and a palm pad no DOF moves, belong to none).
        self.pad_of = {pad.name: i for i, pad in enumerate(hand.pads)}
        self.finger_of_dof = [
            movers[0] if len(movers := [p.name for p in hand.pads if k in p.dofs]) == 1 else None
            for k in range(len(hand.dofs))
        ]

    def start(self, readings: Readings) -> None:
        hand = self.ctx.info.hand
        pre = readings.hand_q.copy() if self.preshape is None else self.preshape.copy()
        moving = (hand.closing != 0) & ~np.isclose(self.grasp, pre, atol=1e-4)
        if self.size is not None:  # open at least this far; closing past the preshape could catch the object
            sized = hand.closed + float(self.size) * (hand.open - hand.closed)
            wider = hand.closing * (pre - sized) > 0
            pre[moving & wider] = sized[moving & wider]
        self.pre, self.moving = pre, moving
        self.fingers = sorted({self.finger_of_dof[i] for i in np.flatnonzero(moving)} - {None})
        self.pinch = len(self.fingers) == 2  # two opposed fingers close on the object along one line
        self.reference = readings.hand_q.copy()
        self.effort = np.zeros_like(self.reference)
        self.pressing = moving  # the DOFs pressed by force once holding
        self.phase = Phase.PRESHAPE
        self.stillness.start(readings.hand_q)
        self.ctx.blackboard.fingers_stopped = False
        self.ctx.blackboard.preshaped = False
        self.ctx.memory[EMPTY_HAND] = world_load(readings)  # a grasp begins empty-handed
        if not self.fingers:
            self.finish(Status.ERROR, "from this posture the grasp shape moves no finger that has a tactile pad")
            self.phase = Phase.FAILED

    def update(self, readings: Readings, dt: float) -> ControlData:
        getattr(self, self.phase.value)(readings, dt)
        return self._command()

    # -- phases: one tick each ------------------------------------------------------------
    def _preshape(self, readings: Readings, dt: float) -> None:
        """Open into the preshape; once made (or blocked short of it, and not freed), wait for the arm."""
        if self._ramp(self.pre, dt, readings.hand_q) or (self._blocked(readings, dt) and not self._free_fingers()):
            self.phase = Phase.WAIT
            self.ctx.blackboard.preshaped = True

    def _wait(self, readings: Readings, dt: float) -> None:
        if self.ctx.blackboard.contact:
            self._begin_closing()

    @abstractmethod
    def _close(self, readings: Readings, dt: float) -> None:
        """One tick of closing; ends by setting `fingers_stopped` and the next phase."""

    @abstractmethod
    def _hold(self, readings: Readings, dt: float) -> None:
        """One tick of holding the object once the fingers have closed."""

    def _failed(self, readings: Readings, dt: float) -> None:
        """Nothing more to do: the fingers stay where they are."""

    # -- shared by the phases -------------------------------------------------------------
    def _free_fingers(self) -> bool:
        """The preshape is blocked short of its posture: true if the arm is asked to rise
        so that the hand can make it in free air (Phase.FREE). The baseline grasp does not."""
        return False

    def _begin_closing(self) -> None:
        self.phase = Phase.CLOSE
        self.stillness.seconds[:] = 0.0
        self.ctx.blackboard.fingers_stopped = False

    def _closed(self, readings: Readings, dt: float) -> bool:
        """One tick of closing: every grasping finger closes until it stands still (on the
        object, or blocked) or reaches its limit; true once all have. A pad touching on
        the way (a fingertip sliding on the table) does not stop a finger: only where the
        fingers end up counts, as a Barrett finger's clutch stops it only when blocked.
        While the arm's sliding grasp backs off a surface the fingertips press on
        (`pressing`), the fingers not yet on the object wait where they are: pressed on
        the table, they would stall there, short of the object."""
        hand = self.ctx.info.hand
        q = readings.hand_q
        waiting = self.moving & ~self._on_object(readings) if self.ctx.blackboard.pressing else np.zeros_like(self.moving)
        closing = self.moving & ~waiting
        step = self.rate * self.slowed * dt
        self.reference[closing] += np.clip(hand.closed[closing] - self.reference[closing], -step[closing], step[closing])
        self.reference[waiting] = q[waiting]
        lead = LEAD * self.range  # how far the reference may run ahead of a blocked finger
        self.reference = np.clip(self.reference, q - lead, q + lead)
        at_limit = self._at_closed(q)
        self._blocked(readings, dt)
        self.stillness.seconds[waiting] = 0.0
        return bool((at_limit | (self.stillness.seconds > STALL_TIME))[self.moving].all())

    def _at_closed(self, q: np.ndarray) -> np.ndarray:
        """Per DOF: within REACHED of its range from closed (a finger short of it stopped on something)."""
        return np.abs(q - self.ctx.info.hand.closed) < REACHED * self.range

    def _on_object(self, readings: Readings) -> np.ndarray:
        """Per DOF: the pad of the finger it moves touches something."""
        pads = readings.pad_force
        return np.array([f is not None and pads[self.pad_of[f]] >= self.touch for f in self.finger_of_dof])

    def _touching(self, readings: Readings) -> list[str]:
        pads = readings.pad_force
        return [f for f in self.fingers if pads[self.pad_of[f]] >= self.touch]

    def _blocked(self, readings: Readings, dt: float) -> bool:
        """Counts how long each DOF has stood still (`Stillness`); true once every moving
        one has, for STALL_TIME (a preshape that meets the object stops there)."""
        return bool((self.stillness.update(readings.hand_q, dt)[self.moving] > STALL_TIME).all())

    # -- commands -------------------------------------------------------------------------
    def _ramp(self, goal: np.ndarray, dt: float, q: np.ndarray, faster: float = 1.0) -> bool:
        step = faster * self.rate * dt
        self.reference += np.clip(goal - self.reference, -step, step)
        return bool((np.abs(goal - q) < REACHED * self.range + 1e-3).all())

    def _command(self) -> ControlData:
        hand = self.ctx.info.hand
        pressing = self.pressing & self.phase.holding
        values = np.where(pressing, hand.closing * self.effort, self.reference)
        modes = tuple(HandMode.FORCE if p else HandMode.POSITION for p in pressing)
        return ControlData(hand=HandCommand(values=values, modes=modes))


class NaiveGraspHand(FingerGrasp):
    """The naive grasp's hand (thesis 3.4.1): preshape, wait for the arm's `contact`, close
    until every finger stops, then add a little effort (`squeeze`) to the fingers whose
    pads touch. No corrections, no force adaptation. Done only once the pads say the
    fingers hold the object (two grasping pads, or each of fewer, touch it); otherwise an
    error naming the fingers that missed it."""

    def __init__(self, ctx: Context) -> None:
        super().__init__(ctx)
        self.squeeze = float(self.params["squeeze"])

    def _close(self, readings: Readings, dt: float) -> None:
        if not self._closed(readings, dt):
            return
        self.ctx.blackboard.fingers_stopped = True
        touching = self._touching(readings)
        if len(touching) < min(2, len(self.fingers)):
            missed = [f for f in self.fingers if f not in touching]
            self.finish(Status.ERROR, f"finger {', '.join(missed)} missed the object" if touching
                        else "nothing between the fingers")
            self.phase = Phase.FAILED
            return
        self.pressing = self.moving & np.array([f in touching for f in self.finger_of_dof])
        self.effort = np.where(self.pressing, self.squeeze * self.ctx.info.hand.effort_limit, 0.0)
        self.phase = Phase.HOLD
        self.finish(Status.DONE, f"closed on the object; touching: {', '.join(touching)}")

    def _hold(self, readings: Readings, dt: float) -> None:
        """The squeeze stays as set."""
