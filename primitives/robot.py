"""The robot interface: everything a primitive may know about, read from and send to a robot.

A primitive sees one arm and its hand through `Robot`, whichever engine (or real robot)
sits below, as the thesis's simulated robot exposes the same inputs and outputs as the
real one (5.4.2). Conventions, shared by every implementation:

- SI units; angles in radians; the ATD world frame (x away from the robot, z up, table
  top at z = 0).
- `tcp` is the tool centre point as a 4x4 world pose; its z axis is the approach
  direction (out of the palm).
- `wrench` = (fx, fy, fz, tx, ty, tz) that the hand, and whatever it touches or holds,
  exerts on the wrist sensor, in the hand frame, raw (it includes the hand's weight):
  hand pointing down at rest reads fz ~ +m_hand g; pressing down makes fz drop.
- Twists are (vx, vy, vz, wx, wy, wz) of the TCP in the world frame.
- A hand DOF is one actuated motion (a Barrett finger with its coupled distal joint, the
  two mirrored jaws of a parallel gripper); `HandInfo.closing` says which way closes.
- A tactile image has its rows along the finger and its columns across it; each taxel
  holds the normal force (N) on it, and `pad_force` the pad's total.
- A depth image is taken on demand (`Robot.capture`), never each tick: rendering one costs
  what hundreds of ticks do.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass, field
from enum import StrEnum
from typing import Callable, Mapping, Sequence

import numpy as np

from atd.model.resolved_rate import TWIST_DAMPING, limited_joint_velocities

SENSORS = ("joints", "wrench", "tactile", "range")
"""Sensor streams whose update counters `Readings.seq` carries."""


class HandMode(StrEnum):
    """How a hand DOF's command value is read."""

    POSITION = "position"  # rad or m, the DOF's position target
    VELOCITY = "velocity"  # rad/s or m/s, the target moves at this rate
    FORCE = "force"  # N m or N, effort along the DOF (positive = its positive direction)


@dataclass(frozen=True)
class PadInfo:
    """A tactile finger pad: `taxels` is (rows, cols) of its array, None where the
    robot only measures one force for the finger; `dofs` are the hand DOFs that move it
    (none for a palm pad), which is how a hand controller knows which finger a pad is on;
    `base` is where that finger stands on the palm, (x, y) in the hand frame (m), which is
    how it knows which way "towards this finger" is; `half_size` is the (x, y) half extent
    of its sensing surface (m), columns of the image along x, rows along y."""

    name: str
    taxels: tuple[int, int] | None
    dofs: tuple[int, ...] = ()
    base: tuple[float, float] = (0.0, 0.0)
    half_size: tuple[float, float] = (0.0, 0.0)


@dataclass(frozen=True)
class HandInfo:
    dofs: tuple[str, ...]
    lower: np.ndarray
    upper: np.ndarray
    velocity_limit: np.ndarray
    effort_limit: np.ndarray
    closing: np.ndarray  # per DOF: +1 or -1 = the direction that closes the hand, 0 = not a closing DOF
    open: np.ndarray  # DOF positions of the fully open hand
    closed: np.ndarray  # DOF positions of the fully closed, empty hand
    postures: Mapping[str, np.ndarray]  # D5 hand shape name (or the hand's push posture) -> DOF positions
    pads: tuple[PadInfo, ...]
    stiffness: np.ndarray  # per DOF: the position servo's effort per unit of position error
    self_locking: np.ndarray  # per DOF: a drive that keeps its torque when pushed back (a worm gear)
    # hand DOF values -> (pads, 4, 4): each pad's sensing surface in the TCP frame (+z out of
    # the finger), the hand's forward kinematics, as a real hand computes it from its encoders
    pad_surfaces: Callable[[np.ndarray], np.ndarray]
    # the hand's model behind the wrist sensor, as a real sensor's gravity compensation has it:
    mass: float  # kg the sensor carries when the hand is empty
    centre_of_mass: Callable[[np.ndarray], np.ndarray]  # hand DOF values -> (3,) its centre, TCP frame
    wrist: np.ndarray  # (3,) the sensor's origin in the TCP frame, about which `wrench` reads torques
    # how much better the hand's surfaces grip than an object's own friction says (rubber pads)
    surface_friction: float = 1.0


@dataclass(frozen=True)
class RobotInfo:
    """What does not change during a run."""

    name: str  # e.g. "melfa", "tombatossals/right"
    control_period: float  # s
    arm_joints: tuple[str, ...]
    arm_lower: np.ndarray
    arm_upper: np.ndarray
    arm_velocity_limit: np.ndarray
    arm_effort_limit: np.ndarray
    home: np.ndarray  # arm joint positions
    hand: HandInfo
    has_range: bool  # an IR range sensor along the approach axis (Baxter)
    range_limits: tuple[float, float] = (0.0, 0.0)  # m, what the range sensor can measure
    cameras: tuple[str, ...] = ()  # depth cameras `Robot.capture` reads

    @property
    def arm_dof(self) -> int:
        return len(self.arm_joints)


@dataclass(frozen=True)
class Readings:
    """One read of every sensor, taken once per control tick.

    `seq` counts the updates of each sensor stream (keys in `SENSORS`); a stream whose
    counter stops moving is frozen. Arrays are owned by the snapshot.
    """

    time: float
    arm_q: np.ndarray
    arm_dq: np.ndarray
    arm_effort: np.ndarray
    hand_q: np.ndarray
    hand_dq: np.ndarray
    hand_effort: np.ndarray
    tcp: np.ndarray  # (4, 4)
    wrench: np.ndarray  # (6,)
    taxels: Mapping[str, np.ndarray | None]  # pad -> (rows, cols) normal force per taxel, N
    pad_force: np.ndarray  # per pad, N, in `HandInfo.pads` order
    range: float | None  # m; inf when nothing is in range; None without a range sensor
    seq: Mapping[str, int] = field(default_factory=dict)


@dataclass(frozen=True)
class DepthImage:
    """One picture of a depth camera. `pose` is the camera's optical frame (z along the
    view, x to the image's right, y down it) in the world as the robot believes it from its
    calibration: where the camera truly stands may differ, and the picture shows the truth."""

    sensor: str
    time: float  # s, when it was taken
    depth: np.ndarray  # (height, width) float32, m along the optical axis; 0 where nothing was seen
    intrinsics: tuple[float, float, float, float]  # (fx, fy, cx, cy), pixels; pixel centres at whole numbers
    pose: np.ndarray  # (4, 4) camera -> world


def point_cloud(image: DepthImage) -> np.ndarray:
    """(n, 3) world points of every pixel that saw something, through the believed pose."""
    rows, cols = np.nonzero(image.depth > 0)
    z = image.depth[rows, cols].astype(float)
    fx, fy, cx, cy = image.intrinsics
    points = np.column_stack([(cols - cx) * z / fx, (rows - cy) * z / fy, z])
    return points @ image.pose[:3, :3].T + image.pose[:3, 3]


class Robot(ABC):
    """One arm and its hand, commanded at the control rate.

    Commands hold until replaced; `step()` applies them for one control period and
    advances time. Commands beyond the velocity or joint limits are clamped.
    """

    #: Damping of the Cartesian velocity solver, in the units of the Jacobian (m).
    twist_damping = TWIST_DAMPING

    info: RobotInfo

    @abstractmethod
    def read(self) -> Readings:
        """All sensors, as of the last step."""

    @abstractmethod
    def jacobian(self) -> np.ndarray:
        """(6, arm_dof) geometric Jacobian of the TCP in the world frame, linear rows first."""

    @abstractmethod
    def command_arm_velocity(self, dq: np.ndarray) -> None:
        """Arm joint velocities, rad/s."""

    def twist_velocities(self, twist: np.ndarray) -> np.ndarray:
        """A TCP twist in the world frame as joint velocities, the same way on every arm:
        damped least squares that spares joints near their limits."""
        info = self.info
        return limited_joint_velocities(self.jacobian(), twist, self.twist_damping, self.read().arm_q,
                                        info.arm_lower, info.arm_upper)

    def command_arm_twist(self, twist: np.ndarray) -> None:
        """A TCP twist in the world frame, as `twist_velocities` turns it into joint speeds."""
        self.command_arm_velocity(self.twist_velocities(np.asarray(twist, float)))

    @abstractmethod
    def command_hand(self, values: Sequence[float] | np.ndarray, modes: HandMode | Sequence[HandMode]) -> None:
        """One value per hand DOF, read according to its mode (one mode for all, or one per DOF)."""

    @abstractmethod
    def step(self) -> None:
        """Advance one control period."""

    @abstractmethod
    def capture(self, sensor: str) -> DepthImage:
        """A picture of the depth camera `sensor` (one of `info.cameras`), taken now."""
