"""The robot interface on PyBullet, same scene, frames and signs as MuJoCo.

Holding by friction needs (sim-notes.md): a small step, friction anchors, enough solver
iterations. Bullet multiplies the friction of the two bodies in contact, so the table and
the arm use 1 and the object's own coefficient (from the ATD) governs its contacts, as
geom priority makes it do in MuJoCo; the hand's surfaces use their description's
`surface_friction` (MuJoCo: explicit contact pairs with the product). Hand joints follow their DOF with mimic targets.
Several arms of one robot are a body each in one client (`arm`), stepped together.
"""

from __future__ import annotations

import os
import tempfile
from dataclasses import dataclass

import numpy as np
import pybullet as pb

from atd.model.frames import GRAVITY
from atd.sim.models import matrix_to_quat, urdf
from atd.sim.scene import (
    CAMERA_AZIMUTH,
    CAMERA_DISTANCE,
    CAMERA_ELEVATION,
    CAMERA_TARGET,
    COLOURS,
    TABLE_CENTRE,
    TABLE_HALF,
    WORKSPACE_CAMERA,
    Body,
    Scene,
    bounding_box,
)
from atd.sim.simrobot import SimRobot
from atd.sim.thread import END_SLACK, Thread, jaws
from factories.description import DepthCamera, RobotDescription

SOLVER_ITERATIONS = 50
ARM_POSITION_GAIN = 0.1
HAND_POSITION_GAIN = 0.3
# The most a coupling (Hand.couplings) resists with, in multiples of its joint's effort: a
# transmission outlasts the motor that drives it.
COUPLING_FORCE = 10.0
# Of a coupling's position error corrected each step: left at Bullet's default, a gear tied
# the joints' speeds only, and one jaw set 17 mm from the other stayed there for 2 s.
COUPLING_ERP = 0.2
#: The renderer's clipping planes, as fractions of a depth camera's near and multiples of its
#: far limit: what lies nearer still hides what is behind it, as on a real camera.
CLIP_NEAR, CLIP_FAR = 0.25, 1.5
#: A thread (atd/sim/thread.py) is two links of the object: its rise's mass (taken from the
#: object's) and inertia, and an inertia added to the cap's turn as MuJoCo's armature (1 mN m at
#: 10 rad/s2): a motor on almost no inertia holds loosely.
NUT_MASS = 0.001  # kg, the rising link (the turning one is the cap)
NUT_INERTIA = (1e-6, 1e-6, 1e-6)  # kg m^2, the rising link's
NUT_TURN_INERTIA = 1e-4  # kg m^2 added to the cap's about its axis while on the thread
#: The most a thread's rise, and a fixture's clamp, resist with (N or N m): far more than a
#: hand pulls or pushes with.
THREAD_FORCE = 1000.0
#: Of the rise's lag behind pitch x turn, the part its motor corrects each step: at Bullet's
#: default (0.1) a cap pinched by the Melfa (10 N a pad) and turned 1 rad rose 0.11 mm of 0.67.
RISE_GAIN = 1.0
#: Towards the light in video frames: where the MuJoCo scene's one light shines from.
LIGHT_DIRECTION = (0.1, -0.4, 1.0)


@dataclass
class _Thread:
    """A threaded object's thread in Bullet: the object, the rise per radian turned, the turn
    at which the cap comes free, the free cap once it has (None before), a test's push."""

    object: int
    thread: Thread
    free: int | None = None
    push: np.ndarray | None = None

    @property
    def rise(self) -> float:
        return self.thread.pitch / (2 * np.pi)

    @property
    def end(self) -> float:
        return self.thread.end_angle - 2 * np.pi * END_SLACK


def _xyzw(m: np.ndarray) -> list[float]:
    w, x, y, z = matrix_to_quat(m[:3, :3])
    return [x, y, z, w]


def _matrix(position, xyzw) -> np.ndarray:
    m = np.eye(4)
    m[:3, :3] = np.array(pb.getMatrixFromQuaternion(xyzw)).reshape(3, 3)
    m[:3, 3] = position
    return m


def _apart(client: int, bodies: list[int]) -> None:
    """The arms' bodies pass through one another, as a robot's own links do (and MuJoCo's arms):
    each carries the robot's trunk in the same place."""
    for k, a in enumerate(bodies):
        for b in bodies[k + 1:]:
            for link_a in range(-1, pb.getNumJoints(a, physicsClientId=client)):
                for link_b in range(-1, pb.getNumJoints(b, physicsClientId=client)):
                    pb.setCollisionFilterPair(a, b, link_a, link_b, 0, physicsClientId=client)


class PybulletRobot(SimRobot):
    engine = "pybullet"

    def __init__(self, description: RobotDescription, scene: Scene, seed: int = 0, window: bool = False,
                 belief: RobotDescription | None = None, others: tuple[RobotDescription, ...] = ()):
        """`others`: further arms of the robot in the same world, each its own body loaded
        here and driven through its own `PybulletRobot`, made with `arm`, and stepped by this one."""
        super().__init__(description, scene, seed, belief)
        d = description
        self.client = c = pb.connect(pb.GUI if window else pb.DIRECT)
        self._owns_client = True
        if window:  # PyBullet's own window, without its side panels, looking where the videos look
            pb.configureDebugVisualizer(pb.COV_ENABLE_GUI, 0, physicsClientId=c)
            pb.resetDebugVisualizerCamera(CAMERA_DISTANCE, CAMERA_AZIMUTH - 90, CAMERA_ELEVATION, CAMERA_TARGET,
                                          physicsClientId=c)
        pb.setTimeStep(d.timestep, physicsClientId=c)
        pb.setGravity(0, 0, -GRAVITY, physicsClientId=c)
        pb.setPhysicsEngineParameter(numSolverIterations=SOLVER_ITERATIONS, physicsClientId=c)
        bodies = [self._load(arm) for arm in (d, *others)]
        _apart(c, bodies)
        self._unbound = bodies[1:]  # the bodies of `others`, in order, until `arm` binds them
        self._bind(bodies[0])
        self._build_scene(scene)
        self._apply_arm(self._q_ref, self._dq_ref)
        self._hold_hand()

    def arm(self, description: RobotDescription, seed: int, belief: RobotDescription | None = None) -> PybulletRobot:
        """The robot interface of the next arm of `others` in this world (in their order),
        which this robot's `step` moves with its own; it shares this world's objects and threads."""
        other = PybulletRobot.__new__(PybulletRobot)
        SimRobot.__init__(other, description, self.scene, seed, belief)
        other.client, other._owns_client = self.client, False
        other._bind(self._unbound.pop(0))
        other._objects, other.object, other._threads = self._objects, self.object, self._threads
        other._apply_arm(other._q_ref, other._dq_ref)
        other._hold_hand()
        self._partners.append(other)
        return other

    def _load(self, d: RobotDescription) -> int:
        """An arm's body, loaded from its URDF where its description places it."""
        fd, path = tempfile.mkstemp(suffix=".urdf")
        try:
            with os.fdopen(fd, "w") as f:
                f.write(urdf(d))
            base = d.base.matrix()
            return pb.loadURDF(path, base[:3, 3].tolist(), _xyzw(base), useFixedBase=True,
                               flags=pb.URDF_USE_INERTIA_FROM_FILE, physicsClientId=self.client)
        finally:
            os.unlink(path)

    def _bind(self, body: int) -> None:
        """Find this arm's joints and links in its `body`, give its surfaces their friction,
        tie its hand's couplings and put it at its home with the hand open."""
        d, c = self.description, self.client
        self.body = body
        index = {}
        for i in range(pb.getNumJoints(self.body, physicsClientId=c)):
            info = pb.getJointInfo(self.body, i, physicsClientId=c)
            index[info[1].decode()] = i
            index["link:" + info[12].decode()] = i
            pb.changeDynamics(self.body, i, lateralFriction=1.0, frictionAnchor=1, physicsClientId=c)
        self._index = index
        joints = list(d.arm_joints) + list(self.hand_joints)
        self._joints = [index[n] for n in joints]
        self._arm = self._joints[: len(d.arm_joints)]
        self._hand = self._joints[len(d.arm_joints):]
        movable = [i for i in range(pb.getNumJoints(self.body, physicsClientId=c))
                   if pb.getJointInfo(self.body, i, physicsClientId=c)[2] != pb.JOINT_FIXED]
        self._movable = movable
        self._jac_columns = [movable.index(i) for i in self._arm]
        self._hand_link = index["link:" + d.hand_root]
        self._pad_links = [index["link:" + p.name] for p in d.hand.pads]
        self._hand_links = [index["link:" + n] for n in d.hand_links if n != d.hand_root] + self._pad_links
        self._hand_set = {self._hand_link, *self._hand_links}
        for link in self._hand_set:  # the hand's surfaces grip d.hand.surface_friction times the object's friction
            pb.changeDynamics(self.body, link, lateralFriction=d.hand.surface_friction, physicsClientId=c)
        self._pad_of_link = {link: k for k, link in enumerate(self._pad_links)}
        self._untouched = (np.zeros(0, int), np.zeros((0, 2)), np.zeros(0))
        self._hand_weights = np.array(  # z of each hand link's weight, root first
            [-GRAVITY * pb.getDynamicsInfo(self.body, i, physicsClientId=c)[0] for i in [self._hand_link, *self._hand_links]]
        )
        self._contact_cache: tuple[tuple, tuple] | None = None
        self._felt: list[tuple[int, tuple, float]] | None = None  # this control period's pad contacts
        self._root_cache: np.ndarray | None = None
        hand_root = d.links_by_name[d.hand_root]
        self._tcp_offset = d.tcp.origin.matrix()
        self._hand_com_h = np.append(hand_root.centre_of_mass, 1.0)
        self._tcp_in_link = list(d.tcp.origin.xyz)  # calculateJacobian takes it in the URDF link frame
        self._range_offset = d.range_sensor.origin.matrix() if d.range_sensor else None
        self._range_link = index["link:" + d.range_sensor.link] if d.range_sensor else -1
        self._arm_effort = np.array([d.joints[n].effort for n in d.arm_joints])
        self._arm_kp = np.array([d.joints[n].servo.kp for n in d.arm_joints])
        self._arm_kv = np.array([d.joints[n].servo.kv for n in d.arm_joints])
        self._gravity = np.zeros(len(d.arm_joints))  # arm joint torques that carry the robot's weight
        self._hand_effort = np.array([d.joints[n].effort for n in self.hand_joints])
        self._hand_kv = np.array([d.joints[n].servo.kv for n in self.hand_joints])
        self._hand_kp = np.array([d.joints[n].servo.kp for n in self.hand_joints])
        self._hand_friction = np.array([d.joints[n].friction for n in self.hand_joints])
        self._driven = np.zeros(0, int)  # self-locking hand joints under a force command, their forces and torques
        self._drive = np.zeros(0)
        self._drive_torque = np.zeros(0)
        self._servo = np.zeros(0, int)  # hand joints under a position servo, and their references
        self._servo_ref = np.zeros(0)
        self._arm_gain = [ARM_POSITION_GAIN] * len(self._arm)

        self._home = dict(zip(d.arm_joints, d.home)) | d.hand_joint_targets(self.info.hand.open)
        for name, i in zip(joints, self._joints):
            pb.resetJointState(self.body, i, self._home.get(name, 0.0), physicsClientId=c)

        for joint, other, ratio in d.hand.couplings:  # one motor's joints move as one; >0 reverses
            gear = pb.createConstraint(self.body, index[joint], self.body, index[other], pb.JOINT_GEAR, (1, 0, 0),
                                       (0, 0, 0), (0, 0, 0), physicsClientId=c)
            pb.changeConstraint(gear, gearRatio=-ratio, erp=COUPLING_ERP,
                                maxForce=COUPLING_FORCE * d.joints[joint].effort, physicsClientId=c)

    def _hold_hand(self) -> None:
        """The hand's servos hold it open, where `_bind` put it."""
        self._apply_hand(np.zeros(len(self._hand), bool), np.array([self._home[n] for n in self.hand_joints]))

    def _set_joints(self, positions: dict[str, float]) -> None:
        self._contact_cache = self._root_cache = self._felt = None
        for name, q in positions.items():
            pb.resetJointState(self.body, self._index[name], q, 0.0, physicsClientId=self.client)

    def _build_scene(self, scene: Scene) -> None:
        c = self.client
        # A friction anchor pins a contact point, which a rolling ball's is not: anchored (on
        # either body), a ball rolling at 5 cm/s sped up to 17 cm/s in 2 s on a level table, and
        # balls the grasp had nudged rolled off it; on a box's floor, one nudged at 2.5 cm/s
        # sped up to 14 cm/s and rolled from wall to wall for half a minute. So nothing fixed that
        # a rolling object may rest on is anchored.
        anchored = not any(body.rolls for body in scene.objects)
        if scene.table:
            table = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=TABLE_HALF, physicsClientId=c)
            self.table = pb.createMultiBody(0, table, basePosition=TABLE_CENTRE, physicsClientId=c)
            pb.changeVisualShape(self.table, -1, rgbaColor=COLOURS["table"], physicsClientId=c)
            pb.changeDynamics(self.table, -1, lateralFriction=1.0, frictionAnchor=int(anchored), physicsClientId=c)
        for obstacle in scene.obstacles:
            self._make(obstacle, fixed=True, colour=COLOURS["obstacle"], anchored=anchored)
        for container in scene.containers:
            for part in container.parts():
                self._make(part, fixed=True, colour=COLOURS["container"], anchored=anchored)
        self._objects = [self._make(body, fixed=False, colour=COLOURS["object"]) for body in scene.objects]
        self.object = self._objects[0] if self._objects else -1
        self._threads = [_Thread(uid, body.thread) for uid, body in zip(self._objects, scene.objects) if body.thread]
        for thread, body in zip(self._threads, [b for b in scene.objects if b.thread]):
            self._hold(thread, body)

    def _hold(self, thread: _Thread, body: Body) -> None:
        """Hold a threaded object's cap on its thread: its turn held by a motor with the thread's
        torque as its most (dry friction), its rise following the turn (`_follow_threads`);
        stand the object in its fixture, if it has one."""
        c, t, uid = self.client, thread.thread, thread.object
        pb.setJointMotorControl2(uid, 1, pb.VELOCITY_CONTROL, targetVelocity=0.0, force=t.torque, physicsClientId=c)
        if t.fixture:
            clamp = pb.createConstraint(uid, -1, -1, -1, pb.JOINT_FIXED, (0, 0, 0), (0, 0, 0),
                                        body.pose[:3, 3].tolist(), childFrameOrientation=_xyzw(body.pose),
                                        physicsClientId=c)
            pb.changeConstraint(clamp, maxForce=THREAD_FORCE, physicsClientId=c)
            for k, (pose, size) in enumerate(jaws(body.pose, bounding_box(body.kind, body.size)[:2], body.size[-1])):
                self._make(Body(f"jaw{k}:{body.name}", "box", size, pose, 1.0, 1.0), fixed=True,
                           colour=COLOURS["obstacle"])

    def _make(self, body: Body, fixed: bool, colour: tuple[float, ...], anchored: bool = True) -> int:
        """The body in Bullet; its contacts keep friction anchors where `anchored` and it does not roll."""
        c = self.client
        half = body.half_extents
        if body.thread is not None:
            return self._threaded(body, colour)
        if body.kind == "box":
            shape = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=half, physicsClientId=c)
        elif body.kind == "cylinder":
            shape = pb.createCollisionShape(pb.GEOM_CYLINDER, radius=half[0], height=2 * half[1], physicsClientId=c)
        elif body.kind == "sphere":
            shape = pb.createCollisionShape(pb.GEOM_SPHERE, radius=half[0], physicsClientId=c)
        else:
            shape = self._mesh_shape(body)
        uid = pb.createMultiBody(
            0 if fixed else body.mass, shape, basePosition=body.pose[:3, 3].tolist(),
            baseOrientation=_xyzw(body.pose), physicsClientId=c,
        )
        pb.changeDynamics(uid, -1, lateralFriction=body.friction, frictionAnchor=int(anchored and not body.rolls),
                          physicsClientId=c)
        pb.changeVisualShape(uid, -1, rgbaColor=colour, physicsClientId=c)
        if not fixed:
            pb.changeDynamics(
                uid, -1, spinningFriction=0.01 * body.friction, rollingFriction=0.0001,
                localInertiaDiagonal=body.inertia(), physicsClientId=c,
            )
        return uid

    def _threaded(self, body: Body, colour: tuple[float, ...]) -> int:
        """A threaded object: main part and neck, then two links on top, the thread's rise
        (prismatic, 1 g) and its turn (revolute), which carries the cap while it is
        on the thread (atd/sim/thread.py). Bullet's gear does not tie a prismatic joint to
        a revolute one (tried: it locked the turn and let the rise slide), so the rise follows
        the turn through a stiff position motor, every physics step (`_follow_threads`)."""
        c, t = self.client, body.thread
        assert t is not None
        height = body.size[-1]
        main_z, neck_z, cap_z = t.parts(height)
        main = (*body.half_extents[:-1], t.main_height(height) / 2)
        if body.kind == "box":
            kinds, sizes = [pb.GEOM_BOX, pb.GEOM_CYLINDER], dict(halfExtents=[main, [0, 0, 0]])
        else:
            kinds, sizes = [pb.GEOM_CYLINDER, pb.GEOM_CYLINDER], {}
        shape = pb.createCollisionShapeArray(
            kinds, radii=[main[0], t.neck_radius], lengths=[2 * main[-1], t.neck_height],
            collisionFramePositions=[[0, 0, main_z], [0, 0, neck_z]], **sizes, physicsClientId=c)
        cap = pb.createCollisionShape(pb.GEOM_CYLINDER, radius=t.cap_radius, height=t.cap_height, physicsClientId=c)
        uid = pb.createMultiBody(
            body.own_mass - NUT_MASS, shape, basePosition=body.pose[:3, 3].tolist(), baseOrientation=_xyzw(body.pose),
            linkMasses=[NUT_MASS, t.cap_mass], linkCollisionShapeIndices=[-1, cap], linkVisualShapeIndices=[-1, -1],
            linkPositions=[[0, 0, cap_z], [0, 0, 0]], linkOrientations=[[0, 0, 0, 1]] * 2,
            linkInertialFramePositions=[[0, 0, 0]] * 2, linkInertialFrameOrientations=[[0, 0, 0, 1]] * 2,
            linkParentIndices=[0, 1], linkJointTypes=[pb.JOINT_PRISMATIC, pb.JOINT_REVOLUTE],
            linkJointAxis=[[0, 0, 1]] * 2, physicsClientId=c)
        pb.changeDynamics(uid, -1, lateralFriction=body.friction, frictionAnchor=1, spinningFriction=0.01 * body.friction,
                          rollingFriction=0.0001, localInertiaDiagonal=body.inertia(), physicsClientId=c)
        pb.changeDynamics(uid, 0, localInertiaDiagonal=NUT_INERTIA, jointLowerLimit=0.0, jointUpperLimit=t.travel,
                          physicsClientId=c)
        inertia = np.add(t.cap_inertia(), (0.0, 0.0, NUT_TURN_INERTIA))
        pb.changeDynamics(uid, 1, lateralFriction=body.friction, frictionAnchor=1, localInertiaDiagonal=inertia.tolist(),
                          jointLowerLimit=0.0, jointUpperLimit=t.end_angle, physicsClientId=c)
        pb.changeVisualShape(uid, -1, rgbaColor=colour, physicsClientId=c)
        pb.changeVisualShape(uid, 1, rgbaColor=COLOURS["cap"], physicsClientId=c)
        return uid

    def _mesh_shape(self, body: Body) -> int:
        """A mesh's convex hull, or a compound of its convex parts (Bullet takes the hull of
        each mesh it is given for a moving body, as MuJoCo does)."""
        c = self.client
        frame = body.mesh_frame if body.mesh_frame is not None else np.eye(4)
        placed = {"meshScale": list(body.mesh_scale), "collisionFramePosition": frame[:3, 3].tolist(),
                  "collisionFrameOrientation": _xyzw(frame)}
        files = body.collision_meshes
        if len(files) == 1:
            return pb.createCollisionShape(pb.GEOM_MESH, fileName=str(files[0]), **placed, physicsClientId=c)
        return pb.createCollisionShapeArray(
            [pb.GEOM_MESH] * len(files), fileNames=[str(f) for f in files], meshScales=[placed["meshScale"]] * len(files),
            collisionFramePositions=[placed["collisionFramePosition"]] * len(files),
            collisionFrameOrientations=[placed["collisionFrameOrientation"]] * len(files), physicsClientId=c,
        )

    # ---- engine part ------------------------------------------------------------------
    def _apply_arm(self, q_ref: np.ndarray, dq_ff: np.ndarray) -> None:
        """The servo pushes like MuJoCo's: gravity compensated (`_advance`), plus at most what
        its kp and kv make of the reference's lead in position and speed. Bullet's position
        motor alone is rigid up to the joint's effort limit: fingertips meeting the table at
        5 mm/s pressed on it with 64 N within one tick (measured) where MuJoCo's pressed with
        about 5 N, and the sliding grasp tared that in as its contact."""
        c = self.client
        states = pb.getJointStates(self.body, self._movable, physicsClientId=c)
        q = np.array([s[0] for s in states])
        dq = np.array([states[i][1] for i in self._jac_columns])
        zeros = [0.0] * len(q)
        self._gravity = np.asarray(pb.calculateInverseDynamics(self.body, q.tolist(), zeros, zeros,
                                                               physicsClientId=c))[self._jac_columns]
        push = self._arm_kp * np.abs(q_ref - q[self._jac_columns]) + self._arm_kv * np.abs(dq_ff - dq)
        pb.setJointMotorControlArray(
            self.body, self._arm, pb.POSITION_CONTROL, targetPositions=q_ref.tolist(), targetVelocities=dq_ff.tolist(),
            forces=np.minimum(self._arm_effort, push).tolist(), positionGains=self._arm_gain,
            physicsClientId=c,
        )

    def _apply_hand(self, force: np.ndarray, values: np.ndarray) -> None:
        """Position joints get a servo (`_servo_hand`). A force joint with a velocity motor that
        runs at F/kv pushing with at most F: in free space it closes at the speed where
        MuJoCo's damped force balances, and against an object it pushes with F, as MuJoCo's
        does. That motor resists being pushed back with F only, so two opposed fingers
        pushing with F are in neutral balance and a held box drifts out; a self-locking
        drive (a joint with dry friction) is therefore modelled as MuJoCo models it: the
        torque F - kv*speed each physics step (`_drive_hand`) against a motor holding still
        with at most the friction."""
        c = self.client
        push = np.clip(values, -self._hand_effort, self._hand_effort)
        self._servo = np.flatnonzero(~force)
        self._servo_ref = values[self._servo]
        locking = force & (self._hand_friction > 0)
        self._driven = np.flatnonzero(locking)
        self._drive = push[self._driven]
        self._drive_torque = self._drive.copy()
        if len(self._driven):
            pb.setJointMotorControlArray(
                self.body, [self._hand[i] for i in self._driven], pb.VELOCITY_CONTROL,
                targetVelocities=[0.0] * len(self._driven), forces=self._hand_friction[self._driven].tolist(),
                physicsClientId=c,
            )
        pushed = np.flatnonzero(force & ~locking)
        if len(pushed):
            pb.setJointMotorControlArray(
                self.body, [self._hand[i] for i in pushed], pb.VELOCITY_CONTROL,
                targetVelocities=(push[pushed] / self._hand_kv[pushed]).tolist(), forces=np.abs(push[pushed]).tolist(),
                physicsClientId=c,
            )

    def _drive_hand(self) -> None:
        """One physics step of the self-locking drives' torque (Bullet clears it every step)."""
        joints = [self._hand[i] for i in self._driven]
        speed = np.array([s[1] for s in pb.getJointStates(self.body, joints, physicsClientId=self.client)])
        self._drive_torque = self._drive - self._hand_kv[self._driven] * speed
        pb.setJointMotorControlArray(self.body, joints, pb.TORQUE_CONTROL, forces=self._drive_torque.tolist(),
                                     physicsClientId=self.client)

    def _servo_hand(self) -> None:
        """Bullet's position motor is rigid up to its force limit, where MuJoCo's servo is a
        spring (kp): a finger whose reference runs ahead of it, blocked by the object or
        the table, pushes with kp times the lag there but with its whole effort limit
        here, and two opposed fingers at their limits squeeze a box out sideways. So each
        physics step the motor's force limit is what the spring would push with. Set once
        per control tick instead, the limit lagged the finger: an SDH2 finger pressed on a
        held object hit it at full limit, bounced, and pressed again every other tick, and
        two-finger grips weakened once the arm stopped (a mug turned 29 degrees in the
        campaign judge's 2 s hold)."""
        servo = self._servo
        if not len(servo):
            return
        joints = [self._hand[i] for i in servo]
        q = np.array([s[0] for s in pb.getJointStates(self.body, joints, physicsClientId=self.client)])
        limit = np.minimum(self._hand_effort[servo], self._hand_kp[servo] * np.abs(self._servo_ref - q))
        pb.setJointMotorControlArray(
            self.body, joints, pb.POSITION_CONTROL, targetPositions=self._servo_ref.tolist(),
            forces=limit.tolist(), positionGains=[HAND_POSITION_GAIN] * len(servo), physicsClientId=self.client,
        )

    def _advance(self) -> None:
        arms = self.arms
        for arm in arms:
            arm._contact_cache = arm._root_cache = None
        feeling = [arm for arm in arms if arm._pad_of_link and arm._squeeze is None]
        for arm in feeling:
            arm._felt = []
        driven = [arm for arm in arms if len(arm._driven)]
        pushed = any(thread.push is not None for thread in self._threads)
        for _ in range(self.substeps):
            for arm in arms:
                arm._servo_hand()
                pb.setJointMotorControlArray(arm.body, arm._arm, pb.TORQUE_CONTROL, forces=arm._gravity.tolist(),
                                             physicsClientId=self.client)
            for arm in driven:
                arm._drive_hand()
            if self._threads:
                self._follow_threads()
            if pushed:
                self._push_caps()
            pb.stepSimulation(physicsClientId=self.client)
            if feeling:
                points = pb.getContactPoints(physicsClientId=self.client)
                for arm in feeling:
                    arm._see_contacts(points)
                    arm._felt.extend(arm._pad_hits())
        for thread in self._threads:  # a cap at the thread's end is let go
            if thread.free is None and pb.getJointState(thread.object, 1, physicsClientId=self.client)[0] >= thread.end:
                self._let_go(thread)

    def _follow_threads(self) -> None:
        """Each cap on its thread rises with its turn: pitch per turn, whatever pulls or pushes it."""
        c = self.client
        for thread in self._threads:
            if thread.free is None:
                turn, speed = pb.getJointState(thread.object, 1, physicsClientId=c)[:2]
                pb.setJointMotorControl2(thread.object, 0, pb.POSITION_CONTROL, targetPosition=thread.rise * turn,
                                         targetVelocity=thread.rise * speed, force=THREAD_FORCE,
                                         positionGain=RISE_GAIN, physicsClientId=c)

    def _let_go(self, thread: _Thread) -> None:
        """The thread's end: the cap goes on as a free body, where it was and as it moved; the
        link that carried it no longer touches anything, is not drawn and stops turning."""
        c, uid, t = self.client, thread.object, thread.thread
        state = pb.getLinkState(uid, 1, computeLinkVelocity=1, computeForwardKinematics=1, physicsClientId=c)
        shape = pb.createCollisionShape(pb.GEOM_CYLINDER, radius=t.cap_radius, height=t.cap_height, physicsClientId=c)
        cap = pb.createMultiBody(t.cap_mass, shape, basePosition=state[0], baseOrientation=state[1], physicsClientId=c)
        friction = pb.getDynamicsInfo(uid, 1, physicsClientId=c)[1]
        pb.changeDynamics(cap, -1, lateralFriction=friction, frictionAnchor=1, spinningFriction=0.01 * friction,
                          rollingFriction=0.0001, localInertiaDiagonal=t.cap_inertia(), physicsClientId=c)
        pb.resetBaseVelocity(cap, state[6], state[7], physicsClientId=c)
        pb.changeVisualShape(cap, -1, rgbaColor=COLOURS["cap"], physicsClientId=c)
        pb.setCollisionFilterGroupMask(uid, 1, 0, 0, physicsClientId=c)
        self._robot_touches(uid, 1, False)  # a pair's filter outranks the mask: `settle` left one on
        pb.changeVisualShape(uid, 1, rgbaColor=(0, 0, 0, 0), physicsClientId=c)
        pb.setJointMotorControl2(uid, 1, pb.VELOCITY_CONTROL, targetVelocity=0.0, force=THREAD_FORCE, physicsClientId=c)
        thread.free = cap
        if thread.push is not None:  # a test's push on it turns it no further
            thread.push = np.concatenate([thread.push[:3], np.zeros(3)])

    def _push_caps(self) -> None:
        """Bullet clears external forces every step: a test's pushes on caps, applied again."""
        c = self.client
        for thread in self._threads:
            if thread.push is not None:
                uid, link = (thread.object, 1) if thread.free is None else (thread.free, -1)
                centre = pb.getLinkState(uid, 1, physicsClientId=c)[0] if link == 1 else \
                    pb.getBasePositionAndOrientation(uid, physicsClientId=c)[0]
                pb.applyExternalForce(uid, link, thread.push[:3].tolist(), centre, pb.WORLD_FRAME, physicsClientId=c)
                pb.applyExternalTorque(uid, link, thread.push[3:].tolist(), pb.WORLD_FRAME, physicsClientId=c)

    def _push_cap(self, k: int, wrench: np.ndarray) -> None:
        self._threads[k].push = wrench

    def _caps(self) -> list[tuple[float, bool, np.ndarray, bool]]:
        c = self.client
        found = []
        for thread in self._threads:
            turn = pb.getJointState(thread.object, 1, physicsClientId=c)[0]
            if thread.free is None:
                link = pb.getLinkState(thread.object, 1, computeForwardKinematics=1, physicsClientId=c)
                pose = _matrix(link[4], link[5])
                touching = any(pb.getContactPoints(thread.object, arm.body, linkIndexA=1, physicsClientId=c)
                               for arm in self.arms)
            else:
                pose = _matrix(*pb.getBasePositionAndOrientation(thread.free, physicsClientId=c))
                touching = any(pb.getContactPoints(thread.free, arm.body, physicsClientId=c) for arm in self.arms)
            found.append((turn, thread.free is not None, pose, touching))
        return found

    def jacobian(self) -> np.ndarray:
        q = [s[0] for s in pb.getJointStates(self.body, self._movable, physicsClientId=self.client)]
        zeros = [0.0] * len(q)
        lin, ang = pb.calculateJacobian(
            self.body, self._hand_link, self._tcp_in_link, q, zeros, zeros, physicsClientId=self.client
        )
        return np.vstack([np.asarray(lin)[:, self._jac_columns], np.asarray(ang)[:, self._jac_columns]])

    def _joint_state(self):
        states = pb.getJointStates(self.body, self._joints, physicsClientId=self.client)
        q, dq, effort = np.array([(s[0], s[1], s[3]) for s in states]).T
        effort[len(self._arm) + self._driven] = self._drive_torque  # Bullet reports only its motors
        return q, dq, effort

    def _link_pose(self, link: int) -> np.ndarray:
        state = pb.getLinkState(self.body, link, computeForwardKinematics=True, physicsClientId=self.client)
        return _matrix(state[4], state[5])

    def _contacts(self) -> tuple:
        """This tick's contact points with the robot as body A (shared by F/T and tactile).

        Asked for the robot's contacts, Bullet swaps a pair whose internal body A is the other
        body and negates its normal but not its friction directions, so a held object's weight
        read upward on the wrist whenever the object was made after the robot (a mesh object
        is). The unswapped list, turned here, gives every force as it acts on the robot.
        """
        return self._contact_lists()[1]

    def _contact_lists(self) -> tuple[tuple, tuple]:
        """This tick's contact points: Bullet's whole list, and the robot's (`_contacts`)."""
        if self._contact_cache is None:
            self._see_contacts(pb.getContactPoints(physicsClientId=self.client))
        return self._contact_cache

    def _see_contacts(self, points: tuple) -> None:
        """Cache Bullet's whole list `points` and the robot's contacts in it (`_contact_lists`)."""
        found = []
        for p in points:
            if p[1] == self.body:
                found.append(p)
            elif p[2] == self.body:
                found.append((p[0], p[2], p[1], p[4], p[3], p[6], p[5], tuple(-v for v in p[7]), p[8], p[9],
                              p[10], tuple(-v for v in p[11]), p[12], tuple(-v for v in p[13])))
        self._contact_cache = (points, tuple(found))

    def _pad_hits(self) -> list[tuple[int, tuple, float]]:
        """The contacts on the pads now: pad index, point (world frame), normal force."""
        return [(self._pad_of_link[p[3]], p[5], p[9]) for p in self._contacts() if p[3] in self._pad_of_link]

    def _hand_root(self) -> np.ndarray:
        if self._root_cache is None:
            self._root_cache = self._link_pose(self._hand_link)
        return self._root_cache

    def _tcp(self) -> np.ndarray:
        return self._hand_root() @ self._tcp_offset

    def _wrench(self) -> np.ndarray:
        """The hand's weight plus every contact force on it, about the sensor, in the hand frame.

        Bullet's own reaction force at the weld is wrong while the arm moves (fz off by
        about 7 N at 5 cm/s, measured here), so the sensor is modelled quasi-statically:
        the hand's inertia (mass times acceleration, a fraction of a newton here) is left out.
        """
        root = self._hand_root()
        origin = root[:3, 3]
        states = pb.getLinkStates(self.body, self._hand_links, physicsClientId=self.client)
        # Weights pull along -z: r x (0, 0, w) = (r_y w, -r_x w, 0).
        arms = np.array([(root @ self._hand_com_h)[:3], *(s[0] for s in states)]) - origin
        torque = np.array([arms[:, 1] @ self._hand_weights, -(arms[:, 0] @ self._hand_weights), 0.0])
        force = np.array([0.0, 0.0, self._hand_weights.sum()])
        hits = [p for p in self._contacts() if p[3] in self._hand_set]
        if hits:
            c = np.array([(*p[5], *p[7], p[9], p[10], *p[11], p[12], *p[13]) for p in hits])
            f = c[:, 3:6] * c[:, 6:7] + c[:, 8:11] * c[:, 7:8] + c[:, 12:15] * c[:, 11:12]
            r = c[:, 0:3] - origin
            force += f.sum(axis=0)
            torque += (r[:, [1, 2, 0]] * f[:, [2, 0, 1]] - r[:, [2, 0, 1]] * f[:, [1, 2, 0]]).sum(axis=0)
            torque += self._unlisted_couple({p[2] for p in hits})
        rot = root[:3, :3]
        return np.concatenate([force @ rot, torque @ rot])

    def _unlisted_couple(self, touched: set[int]) -> np.ndarray:
        """The couple (world frame) that torsional and rolling friction put on the hand through
        the free bodies only it touches. Bullet applies both at each contact but lists them
        neither with the contact points nor in its joint sensors: the Melfa squeezing a 0.1 kg
        box with 15 N read 0.019 N m off about the squeeze. About such a body's centre of mass
        its weight has no moment and its turning inertia is left out (as the hand's is here),
        so the moment its listed contact forces leave is what the hand's unlisted couple on it
        makes up."""
        couple = np.zeros(3)
        points = self._contact_lists()[0]
        threaded = {thread.object for thread in self._threads}
        for uid in touched.intersection(self._movable_bodies()) - threaded:
            centre = np.asarray(pb.getBasePositionAndOrientation(uid, physicsClientId=self.client)[0])
            moment = np.zeros(3)
            for p in points:
                if uid not in (p[1], p[2]):
                    continue
                other, link = (p[2], p[4]) if p[1] == uid else (p[1], p[3])
                if other != self.body or link not in self._hand_set:
                    break  # something else holds it too: its share is not the hand's to know
                on_a = np.multiply(p[7], p[9]) + np.multiply(p[11], p[10]) + np.multiply(p[13], p[12])
                force, at = (on_a, p[5]) if p[1] == uid else (-on_a, p[6])
                moment += np.cross(np.asarray(at) - centre, force)
            else:
                couple += moment
        return couple

    def _pad_contacts(self):
        """Every physics step's pad contacts of the last control period, each with its share of
        the period's mean force: a jaw servo stepped to each period's reference pushes in one
        or two of its physics steps, which the last step alone may miss (docs/robust-grasp.md,
        `pbw33`). Before any period (a teleported arm), the contacts as they stand."""
        hits, share = (self._pad_hits(), 1.0) if self._felt is None else (self._felt, 1.0 / self.substeps)
        if not hits:
            return self._untouched
        pad = np.array([k for k, _, _ in hits])
        frames = {k: self._link_pose(self._pad_links[k]) for k in set(pad.tolist())}
        xy = np.array([(np.asarray(at) - frames[k][:3, 3]) @ frames[k][:3, :2] for k, at, _ in hits])
        return pad, xy, share * np.array([force for _, _, force in hits])

    def _range(self) -> float:
        pose = self._link_pose(self._range_link) @ self._range_offset
        low, high = self.description.range_limits
        start = pose[:3, 3] + pose[:3, 2] * low
        hit = pb.rayTest(start.tolist(), (pose[:3, 3] + pose[:3, 2] * high).tolist(), physicsClientId=self.client)[0]
        return low + hit[2] * (high - low) if hit[0] >= 0 else np.inf

    def _object_poses(self) -> list[np.ndarray]:
        return [_matrix(*pb.getBasePositionAndOrientation(uid, physicsClientId=self.client)) for uid in self._objects]

    def _object_speeds(self) -> tuple[np.ndarray, np.ndarray]:
        velocities = np.array([pb.getBaseVelocity(uid, physicsClientId=self.client) for uid in self._objects]).reshape(-1, 2, 3)
        return np.linalg.norm(velocities[:, 0], axis=1), np.linalg.norm(velocities[:, 1], axis=1)

    def _robot_collides(self, on: bool) -> None:
        parts = [(uid, -1) for uid in self._movable_bodies()] + [(t.object, 1) for t in self._threads if t.free is None]
        for uid, part in parts:
            self._robot_touches(uid, part, on)

    def _robot_touches(self, uid: int, part: int, on: bool) -> None:
        """Whether the links of every arm in this world collide with link `part` of body `uid`,
        whatever their masks say."""
        for arm in self.arms:
            for link in range(-1, pb.getNumJoints(arm.body, physicsClientId=self.client)):
                pb.setCollisionFilterPair(arm.body, uid, link, part, int(on), physicsClientId=self.client)

    def _camera_matrices(self, camera: DepthCamera, near: float, far: float, aspect: float) -> tuple[list, list]:
        """PyBullet's view and projection matrices of a described camera, from where it truly stands."""
        pose = camera.origin.matrix()
        eye = pose[:3, 3]
        view = pb.computeViewMatrix(eye.tolist(), (eye + pose[:3, 2]).tolist(), (-pose[:3, 1]).tolist(),
                                    physicsClientId=self.client)
        projection = pb.computeProjectionMatrixFOV(camera.fovy, aspect, near, far,
                                                   physicsClientId=self.client)
        return view, projection

    def _render_depth(self, camera: DepthCamera) -> np.ndarray:
        near, far = CLIP_NEAR * camera.near, CLIP_FAR * camera.far
        view, projection = self._camera_matrices(camera, near, far, camera.width / camera.height)
        buffer = pb.getCameraImage(camera.width, camera.height, view, projection, renderer=pb.ER_TINY_RENDERER,
                                   physicsClientId=self.client)[3]
        # The depth buffer is non-linear in depth: 0 at the near plane, 1 at the far one.
        return far * near / (far - (far - near) * np.asarray(buffer, float).reshape(camera.height, camera.width))

    # ---- test hooks ------------------------------------------------------------------

    def place_object(self, pose: np.ndarray) -> None:
        if self.object < 0:
            raise LookupError("the scene has no object")
        pb.resetBasePositionAndOrientation(self.object, pose[:3, 3].tolist(), _xyzw(pose), physicsClientId=self.client)
        pb.resetBaseVelocity(self.object, [0, 0, 0], [0, 0, 0], physicsClientId=self.client)
        for arm in self.arms:
            arm._contact_cache = arm._felt = None

    def render(self, width: int, height: int, camera: str = WORKSPACE_CAMERA) -> np.ndarray:
        """An RGB picture of the scene (software renderer), from the same viewpoints as MuJoCo's."""
        if camera == WORKSPACE_CAMERA:
            az, el = np.radians(CAMERA_AZIMUTH), np.radians(CAMERA_ELEVATION)
            forward = np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])
            eye = np.asarray(CAMERA_TARGET) - CAMERA_DISTANCE * forward  # as MuJoCo places its free camera
            view = pb.computeViewMatrix(eye.tolist(), CAMERA_TARGET, [0, 0, 1], physicsClientId=self.client)
            projection = pb.computeProjectionMatrixFOV(45.0, width / height, 0.05, 5.0, physicsClientId=self.client)
        elif camera in self._cameras:
            view, projection = self._camera_matrices(self._cameras[camera], 0.05, 5.0, width / height)
        else:
            raise LookupError(f"{self.info.name} has no camera '{camera}'")
        image = pb.getCameraImage(width, height, view, projection, renderer=pb.ER_TINY_RENDERER,
                                  lightDirection=LIGHT_DIRECTION, lightAmbientCoeff=0.5, lightDiffuseCoeff=0.5,
                                  physicsClientId=self.client)[2]
        return np.asarray(image, np.uint8).reshape(height, width, 4)[:, :, :3]

    def scene_state(self) -> tuple[list[float], list[tuple], list[tuple]]:
        """Robot joints, object poses, and per thread its rise, its turn and the free cap's pose (None on the thread)."""
        c = self.client
        joints = pb.getJointStates(self.body, range(pb.getNumJoints(self.body, physicsClientId=c)), physicsClientId=c)
        caps = [(*(s[0] for s in pb.getJointStates(t.object, (0, 1), physicsClientId=c)),
                 None if t.free is None else pb.getBasePositionAndOrientation(t.free, physicsClientId=c))
                for t in self._threads]
        return [j[0] for j in joints], [pb.getBasePositionAndOrientation(uid, physicsClientId=c) for uid in self._objects], caps

    def _movable_bodies(self) -> list[int]:
        """The objects, then the caps the threads let go."""
        return self._objects + [thread.free for thread in self._threads if thread.free is not None]

    def set_scene_state(self, state: tuple[list[float], list[tuple], list[tuple]]) -> None:
        joints, objects, caps = state
        c = self.client
        for index, q in enumerate(joints):
            pb.resetJointState(self.body, index, q, physicsClientId=c)
        for uid, (position, orientation) in zip(self._objects, objects):
            pb.resetBasePositionAndOrientation(uid, position, orientation, physicsClientId=c)
        for thread, (rise, turn, free) in zip(self._threads, caps):
            pb.resetJointState(thread.object, 0, rise, physicsClientId=c)
            pb.resetJointState(thread.object, 1, turn, physicsClientId=c)
            if free is not None:
                if thread.free is None:  # this copy's cap comes off where the recorded one did
                    self._let_go(thread)
                assert thread.free is not None
                pb.resetBasePositionAndOrientation(thread.free, *free, physicsClientId=c)

    def show(self) -> None:
        """PyBullet's window draws the physics server's state by itself."""

    def close(self) -> None:
        """Disconnect the world, where this arm made it (another arm's `arm` shares it)."""
        if self._owns_client and pb.isConnected(self.client):
            pb.disconnect(self.client)
