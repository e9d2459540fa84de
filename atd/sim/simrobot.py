"""What both engines share behind the robot interface: command bookkeeping (velocity to
servo references, limits, hand modes), sensor models, and the fault hooks for tests.

An engine subclass only moves numbers in and out of its physics: it applies servo
references, advances the physics, and reports true joint states, the TCP pose, the
wrist wrench in the interface's convention, contacts on pads and the IR range.
"""

from __future__ import annotations

import math
from abc import abstractmethod
from dataclasses import dataclass, replace
from typing import Callable, Mapping, Sequence

import numpy as np

from atd.sim.scene import WORKSPACE_CAMERA, Scene
from atd.sim.sensors import NoisySensors, TaxelImages
from atd.sim.thread import CapState, resting_place
from factories.description import DepthCamera, RobotDescription, SensorModel
from factories.robot_info import robot_info
from primitives.robot import SENSORS, DepthImage, HandMode, Readings, Robot

#: How far (rad or m) an arm servo reference may run ahead of the joint: a blocked arm
#: pushes with a bounded force instead of winding up without end.
REFERENCE_LEASH = 0.02
#: Time to reach full speed from rest: the reference generator limits acceleration to
#: speed limit / RAMP_TIME, as an industrial controller's does, and brakes before limits.
RAMP_TIME = 0.2
# Hand modes as small integers, so a tick compares arrays instead of strings.
POSITION, VELOCITY, FORCE = 0, 1, 2
#: Settling a world (`SimRobot.settle`): an object is at rest below these speeds, all of them
#: for SETTLED_FOR on end; after SETTLE_LIMIT the run starts whatever still moves.
SETTLED_SPEED = 0.005  # m/s
SETTLED_SPIN = 0.1  # rad/s: 1.5 mm/s at the rim of a 3 cm object
SETTLED_FOR = 0.2  # s
SETTLE_LIMIT = 5.0  # s of simulated time
_MODE_CODE = {HandMode.POSITION: POSITION, HandMode.VELOCITY: VELOCITY, HandMode.FORCE: FORCE}


def servo_reference(q: float, q_ref: float, dq_ref: float, dq_cmd: float, lower: float, upper: float,
                    limit: float, accel: float, two_accel: float, period: float) -> tuple[float, float]:
    """One arm joint's reference speed and position for the coming period, from the joint's
    position `q`, the last reference and its speed, and the commanded speed: the command
    within the speed `limit`, the acceleration ramp (`accel` per period) and slow enough to
    stop at a joint limit (`two_accel`: twice the acceleration), the reference within the
    joint limits and within REFERENCE_LEASH of the joint."""
    # Comparisons rather than min() and max(), whose calls cost more than this arithmetic; a
    # NaN command still comes out NaN, as it would from numpy.
    dq_cmd = -limit if -limit > dq_cmd else dq_cmd
    dq_cmd = limit if limit < dq_cmd else dq_cmd
    braking = math.sqrt(two_accel * (q_ref - lower if q_ref > lower else 0.0))
    slowest = dq_ref - accel if dq_ref - accel > -braking else -braking
    braking = math.sqrt(two_accel * (upper - q_ref if upper > q_ref else 0.0))
    fastest = dq_ref + accel if dq_ref + accel < braking else braking
    dq = slowest if slowest > dq_cmd else dq_cmd
    dq = fastest if fastest < dq else dq
    low = lower if lower > q - REFERENCE_LEASH else q - REFERENCE_LEASH
    high = upper if upper < q + REFERENCE_LEASH else q + REFERENCE_LEASH
    q_ref = q_ref + dq * period
    q_ref = low if low > q_ref else q_ref
    return dq, high if high < q_ref else q_ref


@dataclass(frozen=True)
class Settling:
    """How a world came to rest before the run: simulated seconds, and the objects still
    moving when SETTLE_LIMIT ran out (none when all came to rest)."""

    seconds: float
    moving: tuple[str, ...]

    def __str__(self) -> str:
        if self.moving:
            return (f"the world had not settled after {self.seconds:.2f} s of simulated time "
                    f"(still moving: {', '.join(self.moving)}); the run starts from there")
        return f"the world settled in {self.seconds:.2f} s of simulated time before the run"


class SimRobot(Robot):
    """A simulated arm and hand; subclasses bind it to one physics engine."""

    engine = ""

    def __init__(self, description: RobotDescription, scene: Scene, seed: int = 0,
                 belief: RobotDescription | None = None):
        """`description` is the robot as it truly is, and what the simulation runs on: its
        `info` (limits, servos, hand) is the truth's, for this driver alone; the controllers
        know their robot from the factory (`Factory.info`), never from here. `belief` is its
        factory's description (by default the same): the camera poses that pictures report,
        as calibrated, come from it."""
        d = description
        self.description = d
        self.scene = scene
        self.info = robot_info(d)
        self._cameras = {c.name: c for c in d.cameras}
        self._believed_cameras = {c.name: c for c in (belief or d).cameras}
        self._camera_noise = np.random.default_rng([seed, 3])
        # Told of every picture taken (a recording keeps them): pictures are taken on demand,
        # so no tick-by-tick reading carries them.
        self.on_capture: Callable[[DepthImage], None] | None = None
        self.settling: Settling | None = None
        self.hand_joints = tuple(n for n in d.joints if n not in d.arm_joints)
        self.substeps = int(round(d.control_period / d.timestep))
        n_arm = len(d.arm_joints)
        # Hand DOF k is read from its first joint; its command spreads over all its joints.
        self._dof_joint = np.array([n_arm + self.hand_joints.index(dof.joints[0][0]) for dof in d.hand.dofs])
        self._dof_ratio = np.array([dof.joints[0][1] for dof in d.hand.dofs])
        self._joint_dof = np.zeros(len(self.hand_joints), int)
        self._joint_ratio = np.zeros(len(self.hand_joints))
        self._joint_follows = np.zeros(len(self.hand_joints), bool)  # geared to its DOF's first joint
        for k, dof in enumerate(d.hand.dofs):
            for n, (joint, ratio) in enumerate(dof.joints):
                i = self.hand_joints.index(joint)
                self._joint_dof[i], self._joint_ratio[i] = k, ratio
                self._joint_follows[i] = dof.geared and n > 0

        # Every reading of a tick lands in one vector: the sensor-modelled streams first
        # (joint positions, pad forces, wrench, range: encoders and pads are often quantised
        # alike, the wrench and range noisy alike, so each model step is a slice), then
        # joint speeds and efforts.
        n_joints = n_arm + len(self.hand_joints)
        n_pads = len(d.hand.pads)
        streams = [("joints", n_joints), ("tactile", n_pads), ("wrench", 6)] + [("range", 1)] * self.info.has_range
        ideal = SensorModel()
        self._sensors = NoisySensors([(d.sensors.get(s, ideal), size) for s, size in streams], np.random.default_rng(seed),
                                     d.control_period)
        self._streams = tuple(s for s, _ in streams)
        p, w = n_joints, n_joints + n_pads
        dq, effort = self._sensors.size, self._sensors.size + n_joints
        self._pads_at, self._wrench_at, self._range_at = slice(p, p + n_pads), slice(w, w + 6), w + 6
        self._arm_at = (slice(0, n_arm), slice(dq, dq + n_arm), slice(effort, effort + n_arm))
        # Hand DOF readings (q, dq, effort) from their first joints, in one gather and one scaling.
        self._hand_at = np.stack([self._dof_joint, dq + self._dof_joint, effort + self._dof_joint])
        self._hand_scale = np.stack([1 / self._dof_ratio, 1 / self._dof_ratio, self._dof_ratio])
        self._taxels = TaxelImages(d.hand.pads)
        self._pad_names = tuple(p.name for p in d.hand.pads)
        self._every_pad = np.ones(len(d.hand.pads))
        # Where pads have no arrays: the first DOF's closing sense, joint and gear ratio.
        first = (self.info.hand.closing[0], self._dof_joint[0], self._dof_ratio[0])
        self._squeeze = first if d.hand.pad_force_from_effort else None
        self._frozen: set[str] = set()
        self._seq = dict.fromkeys(SENSORS, 0)

        self._time = 0.0
        self._q_ref = self.info.home.copy()
        self._dq_cmd = [0.0] * n_arm  # as commanded, within the speed limits once `servo_reference` takes it
        self._dq_ref = np.zeros(n_arm)  # the command after acceleration and limit shaping
        self._hand_modes = np.zeros(len(d.hand.dofs), int)
        self._hand_given: HandMode | tuple[HandMode, ...] | None = None  # the modes as last commanded
        self._velocity_dofs = False
        self._hand_settled = False  # the same command again would leave the hand's targets as they are
        self._joint_force = np.zeros(len(self.hand_joints), bool)  # hand joints under a force command
        self._following = np.zeros(0, int)  # geared hand joints that follow their DOF's motor joint
        self._hand_values = self.info.hand.open.copy()
        self._hand_target = self.info.hand.open.copy()  # position reference, also for velocity mode
        self._hand_changes = True  # the hand's joint commands need working out on the next step
        limit = self.info.arm_velocity_limit
        self._zero = np.zeros(n_arm)
        # Per joint, what `servo_reference` takes beside the joint's state, as plain floats.
        self._ramps = (self.info.arm_lower.tolist(), self.info.arm_upper.tolist(), limit.tolist(),
                       (limit / RAMP_TIME * d.control_period).tolist(), (2 * limit / RAMP_TIME).tolist())
        self._last: Readings | None = None
        self._partners: list[SimRobot] = []  # other arms in this world, which `step` moves too

    # ---- the robot interface -------------------------------------------------------
    def read(self) -> Readings:
        if self._last is None:
            self._last = self._sample()
        return self._last

    def command_arm_velocity(self, dq: np.ndarray) -> None:
        self._dq_cmd = np.asarray(dq, float).tolist()

    def command_hand(self, values: Sequence[float] | np.ndarray, modes: HandMode | Sequence[HandMode]) -> None:
        values = np.asarray(values, float)
        modes = modes if isinstance(modes, str) else tuple(modes)
        # The executor repeats the command every tick: the same one again changes nothing once
        # no DOF restarts from where it is (a DOF moving at a velocity always does).
        if self._hand_settled and modes == self._hand_given and values.tobytes() == self._hand_values.tobytes():
            return
        hand = self.info.hand
        n = len(hand.dofs)
        given = modes
        modes = [modes] * n if isinstance(modes, str) else list(modes)
        if values.shape != (n,) or len(modes) != n:
            raise ValueError(f"{self.info.name}: give one hand value and mode per DOF ({', '.join(hand.dofs)})")
        codes = np.array([_MODE_CODE[HandMode(m)] for m in modes])
        was_force = self._hand_modes == FORCE
        self._hand_given = given
        self._hand_modes = codes
        self._hand_values = values.copy()
        self._velocity_dofs = bool((codes == VELOCITY).any())
        force_dof = codes[self._joint_dof] == FORCE
        self._following = np.flatnonzero(force_dof & self._joint_follows)
        self._joint_force = force_dof & ~self._joint_follows
        position = codes == POSITION
        self._hand_target[position] = np.clip(values[position], hand.lower[position], hand.upper[position])
        # A DOF leaving force mode, or starting to move at a velocity, starts from where it is.
        restart = (codes == VELOCITY) | (was_force & (codes != FORCE))
        self._hand_settled = not restart.any()
        if not self._hand_settled:
            self._hand_target[restart] = self.read().hand_q[restart]
        self._hand_changes = True

    def step(self) -> None:
        """One control period: this arm's commands, and those of the other arms in its world
        (`_partners`), applied; the physics advanced; this arm's sensors sampled, the others'
        when they are read next."""
        for partner in self._partners:
            partner._command()
        self._command()
        self._advance()
        for partner in self._partners:
            partner._time += partner.info.control_period
            partner._last = None
        self._time += self.info.control_period
        self._last = self._sample()

    def _command(self) -> None:
        """The arm's servo references for the coming period, and the hand's joint commands."""
        speeds, references = [], []
        period = self.info.control_period
        # Joint by joint in plain floats: a handful of numbers, where each numpy call on them
        # cost more than all its arithmetic (the same IEEE operations, in the same order).
        for joint in zip(self.read().arm_q.tolist(), self._q_ref.tolist(), self._dq_ref.tolist(),
                         self._dq_cmd, *self._ramps):
            dq, q_ref = servo_reference(*joint, period)
            speeds.append(dq)
            references.append(q_ref)
        self._q_ref, self._dq_ref = np.array(references), np.array(speeds)
        self._apply_arm(self._q_ref, self._dq_ref)
        if self._hand_changes:
            self._update_hand()

    def _update_hand(self) -> None:
        """Turn the DOF commands into joint commands; needed each tick only while a target
        moves (velocity mode) or a geared joint follows its motor joint (force mode)."""
        hand = self.info.hand
        if self._velocity_dofs:
            velocity = self._hand_modes == VELOCITY
            rate = np.minimum(np.maximum(self._hand_values, -hand.velocity_limit), hand.velocity_limit)
            target = self._hand_target + rate * self.info.control_period
            target = np.minimum(np.maximum(target, hand.lower), hand.upper)
            self._hand_target = np.where(velocity, target, self._hand_target)
        dof, ratio, following = self._joint_dof, self._joint_ratio, self._following
        joint_values = np.where(self._joint_force, self._hand_values[dof], self._hand_target[dof]) * ratio
        if len(following):
            # Under a force command a geared joint follows where its DOF's motor joint is.
            joint_values[following] = self.read().hand_q[dof[following]] * ratio[following]
        self._apply_hand(self._joint_force, joint_values)
        self._hand_changes = self._velocity_dofs or len(following) > 0

    # ---- fault hooks, for tests of the layers above (not part of the interface) ---------
    def freeze(self, sensor: str) -> None:
        """Stop a sensor stream updating, as a stuck driver would."""
        if sensor not in SENSORS:
            raise ValueError(f"unknown sensor '{sensor}'; one of {', '.join(SENSORS)}")
        self._frozen.add(sensor)

    def unfreeze(self, sensor: str) -> None:
        self._frozen.discard(sensor)

    def reset_arm(self, q: np.ndarray) -> None:
        """Teleport the arm to `q`, at rest, holding there."""
        q = np.asarray(q, float)
        self._set_joints(dict(zip(self.info.arm_joints, q)))
        self._q_ref = q.copy()
        self._dq_cmd = [0.0] * len(q)
        self._dq_ref = np.zeros_like(q)
        self._apply_arm(self._q_ref, self._dq_ref)
        self._last = self._sample()

    def true_tcp(self) -> np.ndarray:
        """True 4x4 TCP pose (for checks, not for primitives)."""
        return self._tcp()

    @property
    def arms(self) -> tuple[SimRobot, ...]:
        """This arm, then the other arms in its world (a two-arm task's)."""
        return (self, *self._partners)

    def true_joints(self) -> np.ndarray:
        """True positions of the arm joints then `hand_joints`, of every arm in `arms` (for
        recordings, not for primitives)."""
        return np.concatenate([arm._joint_state()[0] for arm in self.arms])

    def true_pad_contacts(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """True contacts on the pads (for recordings, not for primitives): pad index, point
        in that pad's frame, normal force."""
        return self._pad_contacts()

    def hold_still(self, seconds: float) -> None:
        """Keep the arm still and the hand as last commanded for `seconds` of simulated time."""
        self.command_arm_velocity(np.zeros(len(self.info.arm_joints)))
        for _ in range(int(round(seconds / self.info.control_period))):
            self.step()

    def capture(self, sensor: str) -> DepthImage:
        believed = self._believed_cameras.get(sensor)
        camera = self._cameras.get(sensor)
        if believed is None or camera is None:
            raise LookupError(f"{self.info.name} has no depth camera '{sensor}'; "
                              f"its cameras: {', '.join(self.info.cameras) or 'none'}")
        depth = self._render_depth(camera).astype(np.float32)
        depth[(depth < camera.near) | (depth > camera.far)] = 0.0
        if camera.noise:
            seen = depth > 0
            depth[seen] += (camera.noise * depth[seen] ** 2 * self._camera_noise.standard_normal(int(seen.sum())))
        image = DepthImage(sensor, self._time, depth, believed.intrinsics, believed.origin.matrix())
        if self.on_capture is not None:
            self.on_capture(image)
        return image

    def settle(self) -> Settling:
        """Let gravity bring the scene's objects to rest before the run's clock starts (a
        world file's dropped or stacked objects). The robot holds its home, parked, and out
        of their way: they fall through it, as if put there before it came."""
        period = self.info.control_period
        still, elapsed = 0.0, 0.0
        self._robot_collides(False)
        try:
            while elapsed < SETTLE_LIMIT - 1e-9 and still < SETTLED_FOR - 1e-9:
                for arm in self.arms:
                    arm._apply_arm(arm._q_ref, arm._zero)
                self._advance()
                elapsed += period
                linear, angular = self._object_speeds()
                at_rest = bool((linear < SETTLED_SPEED).all() and (angular < SETTLED_SPIN).all())
                still = still + period if at_rest else 0.0
        finally:
            self._robot_collides(True)
        for arm in self.arms:
            arm._last = None
        moving = () if still >= SETTLED_FOR - 1e-9 else tuple(
            b.name for b, v, w in zip(self.scene.objects, *self._object_speeds())
            if v >= SETTLED_SPEED or w >= SETTLED_SPIN)
        self.settling = Settling(elapsed, moving)
        return self.settling

    def object_poses(self) -> dict[str, np.ndarray]:
        """True 4x4 pose of every object by name (for judges and recordings, not for primitives)."""
        return dict(zip((b.name for b in self.scene.objects), self._object_poses()))

    def object_pose(self) -> np.ndarray:
        """True 4x4 pose of the scene's first object (for checks, not for primitives)."""
        if not self.scene.objects:
            raise LookupError("the scene has no object")
        return self._object_poses()[0]

    def objects_inside(self, container: str) -> list[str]:
        """The objects truly in the named container now (for judges, not for primitives)."""
        box = self.scene.container(container)
        return [name for name, pose in self.object_poses().items() if box.holds(pose[:3, 3])]

    def recorded_poses(self) -> dict[str, np.ndarray]:
        """What a recording's truth holds (not for primitives): every object's pose by name,
        then each screw cap's as `NAME:cap`."""
        return self.object_poses() | {f"{name}:cap": cap.pose for name, cap in self.caps().items()}

    def caps(self) -> dict[str, CapState]:
        """The truth about each screw cap, by its object's name (for judges, not for
        primitives): how far it was turned, whether it is off the thread, where it rests."""
        poses = self._object_poses()
        threaded = [(k, b) for k, b in enumerate(self.scene.objects) if b.thread is not None]
        return {body.name: CapState(turned, free, pose,
                                    resting_place(body.thread, body.size[-1], poses[k], pose, free, touching))
                for (k, body), (turned, free, pose, touching) in zip(threaded, self._caps())}

    def push_cap(self, name: str, torque: float = 0.0, force: Sequence[float] = (0.0, 0.0, 0.0)) -> None:
        """Turn the named object's cap with `torque` (N m about its axis as it stands now,
        unscrewing positive) and push it with `force` (N, world x y z), every physics step from now
        until pushed again or, for the torque, until the thread lets the cap go (a test's
        hand on the cap, not part of the interface: it lets go of a cap that comes free, which
        the torque alone would spin up without end)."""
        threaded = [b.name for b in self.scene.objects if b.thread is not None]
        if name not in threaded:
            raise LookupError(f"no object '{name}' with a screw cap; those with one: {', '.join(threaded) or 'none'}")
        k = threaded.index(name)
        axis = self._caps()[k][2][:3, 2]
        self._push_cap(k, np.concatenate([np.asarray(force, float), torque * axis]))

    @abstractmethod
    def arm(self, description: RobotDescription, seed: int, belief: RobotDescription | None = None) -> SimRobot:
        """The robot interface of the next further arm this world was built with (its
        `others`, in order), its sensor noise drawn from `seed`; this robot's `step` moves it
        with its own."""

    @abstractmethod
    def _push_cap(self, k: int, wrench: np.ndarray) -> None:
        """Apply `wrench` (force, torque; world frame, about the centre of mass) to the k-th
        threaded object's cap every physics step until called again."""

    @abstractmethod
    def place_object(self, pose: np.ndarray) -> None:
        """Teleport the object, at rest (moving it away removes it from the task)."""

    @abstractmethod
    def render(self, width: int, height: int, camera: str = WORKSPACE_CAMERA) -> np.ndarray:
        """An RGB picture (height, width, 3) of the scene, for videos: from the free camera on the
        work area, or from one of the robot's described cameras (LookupError for another name)."""

    @abstractmethod
    def scene_state(self) -> object:
        """What a picture of the scene depends on (joint positions, object poses), small and
        picklable: a copy of this robot made by fork renders it after `set_scene_state`."""

    @abstractmethod
    def set_scene_state(self, state: object) -> None:
        """Pose the robot and the objects as `scene_state` found them, for a picture (the
        physics is not stepped: this copy only renders)."""

    @abstractmethod
    def show(self) -> None:
        """Bring the engine's window (opened with `window=True`) up to date."""

    @abstractmethod
    def close(self) -> None:
        """Release the engine."""

    # ---- the engine's part --------------------------------------------------------------
    @abstractmethod
    def _apply_arm(self, q_ref: np.ndarray, dq_ff: np.ndarray) -> None:
        """Servo references for the arm joints, with velocity feed-forward."""

    @abstractmethod
    def _apply_hand(self, force: np.ndarray, values: np.ndarray) -> None:
        """Per hand joint: a force (where `force`) or a position reference."""

    @abstractmethod
    def _set_joints(self, positions: dict[str, float]) -> None:
        """Teleport joints, at rest, and bring poses and sensors up to date."""

    @abstractmethod
    def _advance(self) -> None:
        """Run the physics for one control period."""

    @abstractmethod
    def _joint_state(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """True (q, dq, effort) of arm joints then `hand_joints`."""

    @abstractmethod
    def _tcp(self) -> np.ndarray:
        """True TCP pose."""

    @abstractmethod
    def _wrench(self) -> np.ndarray:
        """True wrist wrench in the interface's convention."""

    @abstractmethod
    def _pad_contacts(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Contacts on pads: pad index (k,), point in that pad's frame (k, 2), normal force (k,)."""

    def _pads_pressed(self) -> bool:
        """Whether any pad contact carries a force now; an engine that can tell without
        working out the contact points (`_pad_contacts`) says so, sparing a tick that work."""
        return True

    @abstractmethod
    def _range(self) -> float:
        """True distance along the IR sensor's axis, inf when nothing is in range."""

    @abstractmethod
    def _object_poses(self) -> list[np.ndarray]:
        """True 4x4 pose of each object, in the scene's order."""

    @abstractmethod
    def _caps(self) -> list[tuple[float, bool, np.ndarray, bool]]:
        """Of each threaded object, in the scene's order: the angle its cap was turned open
        (rad), whether the thread let it go, its 4x4 pose, whether it touches the robot."""

    @abstractmethod
    def _object_speeds(self) -> tuple[np.ndarray, np.ndarray]:
        """Each object's linear (m/s) and angular (rad/s) speed, in the scene's order."""

    @abstractmethod
    def _robot_collides(self, on: bool) -> None:
        """Let the robot touch the objects, or let them pass through it."""

    @abstractmethod
    def _render_depth(self, camera: DepthCamera) -> np.ndarray:
        """(height, width) depth along the optical axis, m, from where `camera` truly stands."""

    # ---- sampling --------------------------------------------------------------------------
    def _sample(self) -> Readings:
        """Every sensor, read now: true values into one vector, the sensor models over it in
        one go, and the snapshot's arrays as views of that vector (which only it owns)."""
        q, dq, effort = self._joint_state()
        taxels, pad_force = self._tactile(effort)
        distance = (self._range(),) if self.info.has_range else ()
        x = np.concatenate((q, pad_force, self._wrench(), distance, dq, effort))
        self._sensors(x)
        hand = x[self._hand_at] * self._hand_scale
        for stream in self._streams:
            if stream not in self._frozen:
                self._seq[stream] += 1
        arm_q, arm_dq, arm_effort = self._arm_at
        readings = Readings(
            time=self._time, arm_q=x[arm_q], arm_dq=x[arm_dq], arm_effort=x[arm_effort],
            hand_q=hand[0], hand_dq=hand[1], hand_effort=hand[2], tcp=self._tcp(), wrench=x[self._wrench_at],
            taxels=taxels, pad_force=x[self._pads_at], range=float(x[self._range_at]) if distance else None, seq=dict(self._seq),
        )
        if self._frozen and self._last is not None:
            return self._hold_frozen(readings, self._last)
        return readings

    def _hold_frozen(self, now: Readings, last: Readings) -> Readings:
        """`now` with each frozen stream's fields as they were (its model keeps running)."""
        held = {}
        if "joints" in self._frozen:
            held |= {f: getattr(last, f) for f in ("arm_q", "arm_dq", "arm_effort", "hand_q", "hand_dq", "hand_effort")}
        if "wrench" in self._frozen:
            held["wrench"] = last.wrench
        if "tactile" in self._frozen:
            held |= {"taxels": last.taxels, "pad_force": last.pad_force}
        if "range" in self._frozen:
            held["range"] = last.range
        return replace(now, **held)

    def _tactile(self, effort: np.ndarray) -> tuple[Mapping[str, np.ndarray | None], np.ndarray]:
        """True taxel images and pad forces, from joint efforts where the hand has no arrays."""
        if self._squeeze is not None:
            # No tactile array: each finger reports the grip force its DOF measures.
            closing, joint, ratio = self._squeeze
            force = max(0.0, closing * (effort[joint] * ratio))
            return dict.fromkeys(self._pad_names), self._every_pad * force
        if not self._pads_pressed():  # most ticks of a run: no contact points to work out
            return self._taxels.untouched
        return self._taxels(*self._pad_contacts())
