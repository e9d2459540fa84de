"""What a primitive controller and a condition are to the executor that runs them.

D5 2.2.4: each ESTD state runs an arm controller and a hand controller together; each
returns `ControlData` for the degrees of freedom it drives, and the control arbitrator
merges them into one command. Conditions watch the sensors (and the controllers'
status) and decide when an abstract event has happened. Both see the robot only
through `primitives.robot`, so they run unchanged on either engine.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass, field
from enum import StrEnum
from types import MappingProxyType
from typing import Any, Callable, Mapping

import numpy as np

from atd.model.controllers import ParamValue
from atd.model.task import Environment, ObjectInfo
from primitives.blackboard import Blackboard
from primitives.robot import DepthImage, HandMode, Readings, RobotInfo


class Status(StrEnum):
    """Where a controller stands; conditions such as `arm_done` read it."""

    RUNNING = "running"
    DONE = "done"  # reached what it was for
    ERROR = "error"  # gave up: the task should take its error edge
    FAULT = "fault"  # the hardware misbehaved: limit, saturation, tracking error


@dataclass
class ArmCommand:
    """An arm contribution: a TCP twist (world frame) and/or joint velocities."""

    twist: np.ndarray | None = None  # (6,) vx vy vz wx wy wz
    joint_velocity: np.ndarray | None = None  # (arm_dof,)
    weight: float = 1.0


@dataclass
class HandCommand:
    """A hand contribution: one value per hand DOF and how to read it; NaN = not driven."""

    values: np.ndarray
    modes: tuple[HandMode, ...]
    weight: float = 1.0


@dataclass
class ControlData:
    """One controller's output for one control tick (D5 2.2.4)."""

    arm: ArmCommand | None = None
    hand: HandCommand | None = None


@dataclass
class Context:
    """What a controller or condition is built with: the robot, its parameters (defaults
    already filled in), the task's world knowledge, and a blackboard shared by everything
    running in the same state (e.g. the arm side of a grasp telling the hand side that the
    palm touched the object)."""

    info: RobotInfo
    params: Mapping[str, ParamValue]
    object: ObjectInfo | None = None
    environment: Environment | None = None
    blackboard: Blackboard = field(default_factory=Blackboard)
    # What the robot has learnt so far in this run, shared by every state (each state's
    # context is the run's with a fresh blackboard): see `primitives.blackboard.EMPTY_HAND`.
    memory: dict[str, Any] = field(default_factory=dict)
    rng: np.random.Generator = field(default_factory=lambda: np.random.default_rng(0))
    # Takes a picture with the named depth camera now (`Robot.capture`): a camera is read on
    # demand, never each tick. None where nothing runs (an ESTD checked before its run).
    camera: Callable[[str], DepthImage] | None = None


class Controller(ABC):
    """A primitive controller: started on entering a state, updated every control tick."""

    def __init__(self, ctx: Context) -> None:
        self.ctx = ctx
        self.params = ctx.params
        self.status = Status.RUNNING
        self.reason = ""  # why it is done, gave up or faulted, for the trace
        self.counts: dict[str, int] = {}  # what it counted on the way, for the trace beside the reason

    def finish(self, status: Status, reason: str, **counts: int) -> None:
        """End with `status`, saying why; `counts` (e.g. an unscrew's `twists`) travel with the
        reason into the trace as numbers, so nothing reads them back out of its words."""
        if self.status is Status.RUNNING:
            self.status, self.reason, self.counts = status, reason, counts

    @abstractmethod
    def start(self, readings: Readings) -> None:
        """Called once, with the readings of the tick the state was entered on."""

    @abstractmethod
    def update(self, readings: Readings, dt: float) -> ControlData:
        """The command for this tick."""


@dataclass
class StateView:
    """What a condition may know of the state it guards."""

    elapsed: float  # s since the state was entered
    arm: Status
    hand: Status
    subtask: Status | None = None  # DONE / ERROR once a sub-task's machine has ended
    subtask_end: str | None = None  # the end state it ended in
    reasons: dict[str, str] = field(default_factory=dict)
    counts: dict[str, dict[str, int]] = field(default_factory=dict)  # "arm"/"hand": what its controller's end counted


class Condition(ABC):
    """A leaf condition: a test on sensors or controller status, possibly debounced.

    `evidence` holds the readings that made the last verdict, so a run can say why an
    event fired ("grasp_lost: pad forces 0.0 0.1 N < 0.5 N for 0.05 s"). It is read on the
    tick the event fires: a condition tested every tick may work it out only then, from
    what its latest verdict kept.
    """

    evidence: Mapping[str, Any] = MappingProxyType({})  # before any verdict has set its own

    def __init__(self, ctx: Context, sensors: tuple[str, ...] = ()) -> None:
        self.ctx = ctx
        self.params = ctx.params
        self.sensors = sensors

    def start(self, readings: Readings) -> None:
        """Called when the state is entered; conditions that tare or count time reset here."""

    @abstractmethod
    def holds(self, readings: Readings, state: StateView, dt: float) -> bool:
        """Whether the condition holds at this tick (called every tick, never short-circuited)."""
