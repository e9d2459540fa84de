"""The robot interface on MuJoCo (the primary engine).

Arm joints: position servos with velocity feed-forward and gravity compensation of the
arm's own links (industrial controllers do the same). Hand joints: affine actuators
switched between a position servo (kp, kv) and a damped push (force - kv * speed).
"""

from __future__ import annotations

import mujoco
import numpy as np

from atd.model.meshcheck import read_mesh
from atd.sim.models import mjcf, object_name, thread_names, visual_meshes
from atd.sim.scene import (CAMERA_AZIMUTH, CAMERA_DISTANCE, CAMERA_ELEVATION, CAMERA_TARGET, WORKSPACE_CAMERA, Scene,
                           SceneError)
from atd.sim.simrobot import SimRobot
from atd.sim.thread import END_SLACK
from atd.sim.mujoco_arms import arm_prefix, arms_mjcf
from factories.description import DepthCamera, RobotDescription


#: The renderer's quality for video frames: no multisampling, coarser spheres and capsules
#: (12 slices, 8 stacks: still round at 640x480), one quad per box face. On a machine without
#: a GPU (software OpenGL, llvmpipe) they took a 640x480 frame from 24 to 12 ms, measured one
#: after the other on a loaded 2-core machine; shadows,
#: off as well, from 60-600 ms to 20.
VIDEO_QUALITY = {"offsamples": 0, "numslices": 12, "numstacks": 8, "numquads": 1}


def video_renderer(model: mujoco.MjModel, width: int, height: int) -> mujoco.Renderer:
    """A renderer for video frames at VIDEO_QUALITY, without shadows. The scene's light and
    the headlight still shade it."""
    quality = model.vis.quality  # read when the renderer's context is made, only then
    kept = {name: getattr(quality, name) for name in VIDEO_QUALITY}
    model.vis.global_.offwidth = max(model.vis.global_.offwidth, width)
    model.vis.global_.offheight = max(model.vis.global_.offheight, height)
    try:
        for name, value in VIDEO_QUALITY.items():
            setattr(quality, name, value)
        renderer = mujoco.Renderer(model, height, width)
    finally:
        for name, value in kept.items():
            setattr(quality, name, value)
    renderer.scene.flags[mujoco.mjtRndFlag.mjRND_SHADOW] = False
    return renderer


def workspace_view() -> mujoco.MjvCamera:
    """The free camera on the work area that videos look through by default."""
    view = mujoco.MjvCamera()
    view.lookat[:] = CAMERA_TARGET
    view.distance, view.azimuth, view.elevation = CAMERA_DISTANCE, CAMERA_AZIMUTH, CAMERA_ELEVATION
    return view


def _id(m: mujoco.MjModel, kind: mujoco.mjtObj, name: str) -> int:
    return mujoco.mj_name2id(m, kind, name)


def compile_mjcf(xml: str, description: RobotDescription, others: tuple[RobotDescription, ...] = ()) -> mujoco.MjModel:
    """The model of `mjcf(description, ...)` (or `arms_mjcf` with `others`): what
    `MjModel.from_xml_string` makes of it, with the visual meshes given as the triangles of
    every object of their files."""
    spec = mujoco.MjSpec.from_string(xml)
    for d, prefix in [(description, "")] + [(o, arm_prefix(o.arm)) for o in others]:
        for name, shape in visual_meshes(d).items():
            vertices, faces = read_mesh(shape.mesh, shape.size)  # type: ignore[arg-type]
            mesh = spec.mesh(prefix + name)
            mesh.file, mesh.scale = "", [1.0, 1.0, 1.0]
            mesh.uservert, mesh.userface = vertices.ravel(), faces.ravel()
        _hand_friction(spec, d, prefix)
    return spec.compile()


def _hand_friction(spec: mujoco.MjSpec, d: RobotDescription, prefix: str) -> None:
    """The hand's surfaces grip an object `d.hand.surface_friction` times its own friction,
    as Bullet's product makes them: an explicit contact pair per hand geom and object geom
    (the objects are the world's free bodies) replaces MuJoCo's dynamic contact, whose
    friction is the object's alone (priority 1). The pair keeps the object's solref and solimp,
    as its priority gives a dynamic contact: a screw cap's stiffness (`atd.sim.models.cap_timeconst`)
    too. Against the table the hand's own friction is taken (MuJoCo's maximum of the two, as
    Bullet's product with the table's 1)."""
    factor = d.hand.surface_friction
    if factor == 1.0:
        return
    hand = [g for link in d.hand_links for g in spec.body(prefix + link).geoms if g.contype or g.conaffinity]
    objects = [g for body in spec.bodies if any(j.type == mujoco.mjtJoint.mjJNT_FREE for j in body.joints)
               for g in body.geoms]
    for g in hand:
        g.friction[0] = factor * g.friction[0]
        for o in objects:
            slide, spin, roll = o.friction
            spec.add_pair(geomname1=g.name, geomname2=o.name, condim=max(g.condim, o.condim),
                          friction=[factor * slide, factor * slide, spin, roll, roll], solref=o.solref, solimp=o.solimp)


class MujocoRobot(SimRobot):
    engine = "mujoco"

    def __init__(self, description: RobotDescription, scene: Scene, seed: int = 0, window: bool = False,
                 belief: RobotDescription | None = None, others: tuple[RobotDescription, ...] = ()):
        """`others`: further arms of the robot in the same world (`atd.sim.mujoco_arms`); each is
        driven through its own `MujocoRobot`, made with `arm`, and stepped by this one."""
        super().__init__(description, scene, seed, belief)
        d = description
        self.xml = arms_mjcf(d, others, scene) if others else mjcf(d, scene)
        try:
            self.model = m = compile_mjcf(self.xml, d, others)
        except ValueError as exc:  # its compiler refuses what it cannot simulate, e.g. a body of almost no inertia
            raise SceneError(f"MuJoCo cannot simulate this world: {' '.join(str(exc).split())}") from None
        self.data = mujoco.MjData(m)
        mujoco.mj_resetDataKeyframe(m, self.data, 0)
        mujoco.mj_forward(m, self.data)
        self._bind(m, self.data, "", 0)
        self._window = self._open_window() if window else None
        self._apply_arm(self._q_ref, self._dq_ref)

    def arm(self, description: RobotDescription, seed: int, belief: RobotDescription | None = None) -> MujocoRobot:
        """The robot interface of another arm in this world (one of `others`, found by its
        name's prefix), which this robot's `step` moves with its own."""
        other = MujocoRobot.__new__(MujocoRobot)
        SimRobot.__init__(other, description, self.scene, seed, belief)
        before = sum(len(p.description.arm_joints) + len(p.hand_joints) for p in (self, *self._partners))
        other._bind(self.model, self.data, arm_prefix(description.arm), before)
        other._window = None
        other._apply_arm(other._q_ref, other._dq_ref)
        self._partners.append(other)
        return other

    def _bind(self, m: mujoco.MjModel, data: mujoco.MjData, prefix: str, first_actuator: int) -> None:
        """Find this arm's joints, actuators, sites and sensors in the model, by their names
        with `prefix`; its actuators start at `first_actuator`."""
        d = self.description
        self.model, self.data = m, data
        # Views of the data read each tick (fetching them anew from MjData costs more than the read).
        self._qpos, self._qvel, self._qfrc_actuator, self._ctrl = data.qpos, data.qvel, data.qfrc_actuator, data.ctrl
        self._sensordata, self._site_xpos, self._site_xmat = data.sensordata, data.site_xpos, data.site_xmat
        self._geom_xpos, self._geom_xmat = data.geom_xpos.reshape(-1), data.geom_xmat.reshape(-1)

        joints = list(d.arm_joints) + list(self.hand_joints)
        jid = [_id(m, mujoco.mjtObj.mjOBJ_JOINT, prefix + n) for n in joints]
        self._qadr = np.array([m.jnt_qposadr[j] for j in jid], np.intp)  # intp: numpy's fast index type
        self._vadr = np.array([m.jnt_dofadr[j] for j in jid], np.intp)
        self._arm_vadr = self._vadr[: len(d.arm_joints)]
        n_arm = len(d.arm_joints)
        self._arm_act = slice(first_actuator, first_actuator + n_arm)
        self._hand_act = np.arange(first_actuator + n_arm, first_actuator + n_arm + len(self.hand_joints))
        # Velocity feed-forward through the position servo: kp (ref + kv/kp dq) - kp q - kv dq.
        self._kv_over_kp = np.array([d.joints[n].servo.kv / d.joints[n].servo.kp for n in d.arm_joints])
        self._hand_kp = np.array([d.joints[n].servo.kp for n in self.hand_joints])
        self._hand_force = np.zeros(len(self.hand_joints), bool)

        self._tcp_site = _id(m, mujoco.mjtObj.mjOBJ_SITE, prefix + d.tcp.name)
        self._identity = np.eye(4)
        self._jac = np.zeros((6, m.nv))  # translational rows, then rotational: one gather a tick
        force_adr = m.sensor_adr[_id(m, mujoco.mjtObj.mjOBJ_SENSOR, prefix + "wrist_force")]
        torque_adr = m.sensor_adr[_id(m, mujoco.mjtObj.mjOBJ_SENSOR, prefix + "wrist_torque")]
        self._wrench_idx = np.r_[force_adr : force_adr + 3, torque_adr : torque_adr + 3]
        # Each pad's contact sensor: slots of (force in the contact frame, world point), empty
        # ones all zero. Flat indices gather a tick's slots, pad centres and pad axes at once.
        contacts = [_id(m, mujoco.mjtObj.mjOBJ_SENSOR, f"{prefix}{p.name}_contacts") for p in d.hand.pads]
        slots = int(m.sensor_dim[contacts[0]]) // 6 if contacts else 0
        slot = np.array([m.sensor_adr[c] + 6 * np.arange(slots) for c in contacts], np.intp).reshape(-1, slots, 1)
        self._slot_pad = np.repeat(np.arange(len(contacts)), slots)
        self._slot_force = slot.ravel()  # the normal force comes first
        self._slot_point = slot + np.arange(3, 6)
        pad_geom = np.array([_id(m, mujoco.mjtObj.mjOBJ_GEOM, prefix + p.name) for p in d.hand.pads],
                            np.intp).reshape(-1, 1, 1)
        self._slot_centre = np.broadcast_to(3 * pad_geom + np.arange(3), self._slot_point.shape).copy()
        self._pad_axes = 9 * pad_geom + 3 * np.arange(3)[:, None] + np.arange(2)  # x and y columns of each pad's rotation
        self._range_adr = m.sensor_adr[_id(m, mujoco.mjtObj.mjOBJ_SENSOR, prefix + "range")] if d.range_sensor else -1
        self._object_bodies = [_id(m, mujoco.mjtObj.mjOBJ_BODY, object_name(b)) for b in self.scene.objects]
        self._object_qadr = [m.jnt_qposadr[m.body_jntadr[b]] for b in self._object_bodies]
        self._object_dofs = np.array([m.jnt_dofadr[m.body_jntadr[b]] + np.arange(6) for b in self._object_bodies],
                                     np.intp).reshape(-1, 6)
        robot_root = _id(m, mujoco.mjtObj.mjOBJ_BODY, f"{prefix}world_{d.name}")
        self._robot_geoms = np.flatnonzero(m.body_rootid[m.geom_bodyid] == robot_root)
        self._robot_geom_set = frozenset(self._robot_geoms.tolist())
        # Each threaded object's thread: its nut's turn (qpos index), the weld holding the cap,
        # the cap's body, its free joint (qpos index) and geom, and the turn where the thread ends.
        self._threads = []
        for body in self.scene.objects:
            if body.thread is not None:
                names = thread_names(body)
                cap = _id(m, mujoco.mjtObj.mjOBJ_BODY, names["cap"])
                self._threads.append((m.jnt_qposadr[_id(m, mujoco.mjtObj.mjOBJ_JOINT, names["turn"])],
                                      _id(m, mujoco.mjtObj.mjOBJ_EQUALITY, names["thread"]), cap,
                                      m.jnt_qposadr[m.body_jntadr[cap]], _id(m, mujoco.mjtObj.mjOBJ_GEOM, names["cap"]),
                                      body.thread.end_angle - 2 * np.pi * END_SLACK))
        self._robot_contype = m.geom_contype[self._robot_geoms].copy()
        self._renderer: mujoco.Renderer | None = None
        self._depth_renderers: dict[str, mujoco.Renderer] = {}
        self._arm_from: np.ndarray | None = None  # where the arm's reference ramps from; None: hold it
        self._fractions = np.arange(1, self.substeps + 1) / self.substeps  # of the ramp, after each substep
        self._sensing = int(m.opt.disableflags)  # the model's own: sensors on
        self._not_sensing = self._sensing | int(mujoco.mjtDisableBit.mjDSBL_SENSOR)

    # ---- engine part ------------------------------------------------------------------
    def _apply_arm(self, q_ref: np.ndarray, dq_ff: np.ndarray) -> None:
        self._arm_to = q_ref + self._kv_over_kp * dq_ff

    def _apply_hand(self, force: np.ndarray, values: np.ndarray) -> None:
        if (force != self._hand_force).any():
            m = self.model
            for i in np.flatnonzero(force != self._hand_force):
                act = self._hand_act[i]
                kp = 1.0 if force[i] else self._hand_kp[i]
                m.actuator_gainprm[act, 0] = kp
                m.actuator_biasprm[act, 1] = 0.0 if force[i] else -kp
            self._hand_force = force.copy()
        self._ctrl[self._hand_act] = values

    def _set_joints(self, positions: dict[str, float]) -> None:
        m, d = self.model, self.data
        for name, q in positions.items():
            j = _id(m, mujoco.mjtObj.mjOBJ_JOINT, name)
            d.qpos[m.jnt_qposadr[j]] = q
            d.qvel[m.jnt_dofadr[j]] = 0.0
        mujoco.mj_forward(m, d)
        self._arm_from = None  # a teleported arm holds its new reference, it does not ramp there

    def _advance(self) -> None:
        # Sensors and site poses come from the start of the last physics step (1 ms old),
        # as a real sensor's sample is; recomputing them would cost a third of a step.
        # The arm's reference moves in a ramp across the period's physics steps (a first-order
        # hold), as a servo drive interpolates its setpoints: held as a step, it left the servo a
        # growing error each period, and the wrist, sampled at the period's end, read a hand
        # going down 0.5 N heavier than at rest.
        # Every substep's references at once, each element as start + change * (k / substeps).
        arms = (self, *self._partners)
        ramps = [(r._arm_act, r._arm_to if r._arm_from is None else r._arm_from) for r in arms]
        ramps = [(act, start + np.multiply.outer(self._fractions, r._arm_to - start))
                 for r, (act, start) in zip(arms, ramps)]
        # Only the last substep's sensor values are ever read: the others skip the sensors
        # (the wrist's force and torque cost a pass of their own over the bodies); the physics
        # does not read them, so every step is the same, float for float.
        options, last = self.model.opt, self.substeps - 1
        options.disableflags = self._not_sensing
        try:
            for k in range(self.substeps):
                for act, references in ramps:
                    self._ctrl[act] = references[k]
                if k == last:
                    options.disableflags = self._sensing
                mujoco.mj_step(self.model, self.data)
        finally:
            options.disableflags = self._sensing
        for r in arms:
            r._arm_from = r._arm_to
        for turn, weld, cap, _, _, end in self._threads:  # a cap at the thread's end is let go
            if self.data.eq_active[weld] and self._qpos[turn] >= end:
                self.data.eq_active[weld] = 0
                self.data.xfrc_applied[cap, 3:] = 0.0  # a test's push on it turns it no further

    def jacobian(self) -> np.ndarray:
        mujoco.mj_jacSite(self.model, self.data, self._jac[:3], self._jac[3:], self._tcp_site)
        return self._jac[:, self._arm_vadr]

    def _joint_state(self):
        return self._qpos[self._qadr], self._qvel[self._vadr], self._qfrc_actuator[self._vadr]

    def _tcp(self) -> np.ndarray:
        pose = self._identity.copy()
        pose[:3, :3] = self._site_xmat[self._tcp_site].reshape(3, 3)
        pose[:3, 3] = self._site_xpos[self._tcp_site]
        return pose

    def _wrench(self) -> np.ndarray:
        # MuJoCo reports what the arm exerts on the hand; the interface wants the reverse.
        return -self._sensordata[self._wrench_idx]

    def _pads_pressed(self) -> bool:
        return bool(np.count_nonzero(self._sensordata[self._slot_force]))

    def _pad_contacts(self):
        offset = self._sensordata[self._slot_point] - self._geom_xpos[self._slot_centre]
        # Row vectors times each pad's x and y axes: the points in their pad's frame.
        xy = np.matmul(offset, self._geom_xmat[self._pad_axes])
        return self._slot_pad, xy.reshape(-1, 2), self._sensordata[self._slot_force]

    def _range(self) -> float:
        distance = float(self._sensordata[self._range_adr])
        low, high = self.description.range_limits
        return distance if low <= distance <= high else np.inf

    def _object_poses(self) -> list[np.ndarray]:
        poses = []
        for body in self._object_bodies:
            pose = np.eye(4)
            pose[:3, :3] = self.data.xmat[body].reshape(3, 3)
            pose[:3, 3] = self.data.xpos[body]
            poses.append(pose)
        return poses

    def _caps(self) -> list[tuple[float, bool, np.ndarray, bool]]:
        d = self.data
        pairs = d.contact.geom[: d.ncon]
        robot = frozenset().union(*(arm._robot_geom_set for arm in self.arms))  # every arm's: any may hold it
        found = []
        for turn, weld, cap, _, geom, _ in self._threads:
            pose = np.eye(4)
            pose[:3, :3] = d.xmat[cap].reshape(3, 3)
            pose[:3, 3] = d.xpos[cap]
            touching = any(g in robot for a, b in pairs if geom in (a, b) for g in (a, b))
            found.append((float(self._qpos[turn]), not d.eq_active[weld], pose, touching))
        return found

    def _object_speeds(self) -> tuple[np.ndarray, np.ndarray]:
        velocity = self._qvel[self._object_dofs]  # free joints: linear (world), then angular (body)
        return np.linalg.norm(velocity[:, :3], axis=1), np.linalg.norm(velocity[:, 3:], axis=1)

    def _robot_collides(self, on: bool) -> None:
        for r in (self, *self._partners):
            self.model.geom_contype[r._robot_geoms] = r._robot_contype if on else 0

    def _render_depth(self, camera: DepthCamera) -> np.ndarray:
        renderer = self._depth_renderers.get(camera.name)
        if renderer is None:
            renderer = self._depth_renderers[camera.name] = mujoco.Renderer(self.model, camera.height, camera.width)
            renderer.enable_depth_rendering()
        renderer.update_scene(self.data, camera.name)
        return renderer.render()

    # ---- test hooks ------------------------------------------------------------------
    def place_object(self, pose: np.ndarray) -> None:
        if not self._object_bodies:
            raise LookupError("the scene has no object")
        quat = np.zeros(4)
        mujoco.mju_mat2Quat(quat, np.ascontiguousarray(pose[:3, :3]).ravel())
        threaded = self.scene.objects[0].thread is not None  # then its cap, the first, goes with it
        relative = np.linalg.solve(self._object_poses()[0], self._caps()[0][2]) if threaded else None
        a = self._object_qadr[0]
        self.data.qpos[a : a + 7] = np.concatenate([pose[:3, 3], quat])
        self.data.qvel[self._object_dofs[0]] = 0.0
        if relative is not None:
            cap, adr = pose @ relative, self._threads[0][3]
            mujoco.mju_mat2Quat(quat, np.ascontiguousarray(cap[:3, :3]).ravel())
            self.data.qpos[adr : adr + 7] = np.concatenate([cap[:3, 3], quat])
            self.data.qvel[self.model.jnt_dofadr[self.model.body_jntadr[self._threads[0][2]]] + np.arange(6)] = 0.0
        mujoco.mj_forward(self.model, self.data)

    def _push_cap(self, k: int, wrench: np.ndarray) -> None:
        self.data.xfrc_applied[self._threads[k][2]] = wrench

    def render(self, width: int, height: int, camera: str = WORKSPACE_CAMERA) -> np.ndarray:
        """An RGB picture of the scene (needs an OpenGL backend, e.g. MUJOCO_GL=egl)."""
        if camera != WORKSPACE_CAMERA and camera not in self._cameras:
            raise LookupError(f"{self.info.name} has no camera '{camera}'")
        if self._renderer is None or (self._renderer.width, self._renderer.height) != (width, height):
            if self._renderer is not None:
                self._renderer.close()
            self._renderer = video_renderer(self.model, width, height)
        if camera == WORKSPACE_CAMERA:
            self._renderer.update_scene(self.data, workspace_view())
        else:
            self._renderer.update_scene(self.data, camera)
        return self._renderer.render()

    def scene_state(self) -> np.ndarray:
        return self.data.qpos.copy()

    def set_scene_state(self, state: np.ndarray) -> None:
        self.data.qpos[:] = state
        mujoco.mj_kinematics(self.model, self.data)
        mujoco.mj_camlight(self.model, self.data)

    def _open_window(self):
        """MuJoCo's interactive viewer on this model, looking where the videos look."""
        import mujoco.viewer

        window = mujoco.viewer.launch_passive(self.model, self.data, show_left_ui=False, show_right_ui=False)
        with window.lock():
            window.cam.lookat[:] = CAMERA_TARGET
            window.cam.distance, window.cam.azimuth, window.cam.elevation = CAMERA_DISTANCE, CAMERA_AZIMUTH, CAMERA_ELEVATION
        return window

    def show(self) -> None:
        if self._window is not None:
            self._window.sync()

    def close(self) -> None:
        if self._window is not None:
            self._window.close()
            self._window = None
        for renderer in [self._renderer, *self._depth_renderers.values()]:
            if renderer is not None:
                renderer.close()
        self._renderer, self._depth_renderers = None, {}
