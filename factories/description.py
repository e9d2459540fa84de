"""A robot description: the one source of truth from which every simulation model is made.

Frames follow URDF: a link's frame is its joint's frame, placed by `origin` in the parent
link's frame; shapes, sites and the centre of mass are given in the link frame. Capsules
and cylinders lie along their local z axis; a mesh shape is its file's convex hull, as both
engines collide it. One description is one arm with its hand
(plus the fixed body it is mounted on), placed in the ATD world frame by `base`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import Literal

import numpy as np

from atd.model.frames import axis_rotation, rectangle_corners, rotation_rpy, rpy_of
from atd.model.meshcheck import mesh_points

Vec3 = tuple[float, float, float]

# times: pads whose sideways motion along one line, squared and summed, is under this many times
# that across it (twice as far) close from all round, with no line to turn the hand by (the
# Barrett's spherical grasp: 1.0; its pinch, the SDH2's and the grippers': no motion across at all)
CLEAR_LINE = 4.0
# The closing sweep `pinch_reach` looks along for a width: this many steps, then the one it lies in
# halved this many times (2.4 rad of a Barrett finger to 0.04 mrad: far under a millimetre of pad)
PINCH_STEPS = 64
PINCH_HALVINGS = 12


@dataclass(frozen=True)
class Origin:
    xyz: Vec3 = (0.0, 0.0, 0.0)
    """Position in metres, in the parent frame."""
    rpy: Vec3 = (0.0, 0.0, 0.0)
    """Roll, pitch, yaw in radians (URDF order: about fixed x, then y, then z)."""

    def matrix(self) -> np.ndarray:
        """A copy of `_matrix`: callers may change theirs."""
        return self._matrix.copy()

    @cached_property
    def _matrix(self) -> np.ndarray:
        """Made once per origin: forward kinematics asks each link's for every pose it computes."""
        m = np.eye(4)
        m[:3, :3] = rotation_rpy(self.rpy)
        m[:3, 3] = self.xyz
        return m


@dataclass(frozen=True)
class Shape:
    """A collision or visual shape. `size`: box = half extents (3); capsule and cylinder =
    (radius, half length of the axis); sphere = (radius,); mesh = its scale along its axes (3)."""

    kind: Literal["box", "capsule", "cylinder", "sphere", "mesh"]
    """Which shape: box, capsule, cylinder, sphere, or mesh (the convex hull of `mesh`)."""
    size: tuple[float, ...]
    """Box: half extents (3); capsule, cylinder: (radius, half length of the axis); sphere: (radius,);
    mesh: scale along its own axes (3)."""
    origin: Origin = Origin()
    """Pose of the shape in its link frame; capsules and cylinders lie along its z."""
    rgba: tuple[float, float, float, float] = (0.6, 0.6, 0.65, 1.0)
    """Colour the engines draw it in."""
    mesh: Path | None = None
    """A mesh shape's OBJ or STL file (checked by atd.model.meshcheck), its vertices in the shape's frame."""

    @cached_property
    def points(self) -> np.ndarray:
        """A mesh shape's vertices in its own frame, scaled: its convex hull is what the engines collide."""
        if self.mesh is None:
            raise ValueError(f"a {self.kind} shape has no mesh")
        return np.unique(mesh_points(self.mesh, self.size), axis=0)  # type: ignore[arg-type]

    def inertia(self, mass: float) -> Vec3:
        """Principal moments of a solid of this shape about its own centre, along its axes
        (a mesh as the box that bounds it)."""
        if self.kind == "mesh":
            return Shape("box", tuple(np.ptp(self.points, axis=0) / 2)).inertia(mass)
        if self.kind == "box":
            a, b, c = (2 * s for s in self.size)
            return (mass * (b * b + c * c) / 12, mass * (a * a + c * c) / 12, mass * (a * a + b * b) / 12)
        if self.kind == "sphere":
            i = 0.4 * mass * self.size[0] ** 2
            return (i, i, i)
        r, half = self.size
        length = 2 * half + (4 / 3 * r if self.kind == "capsule" else 0)  # caps as extra length, roughly
        side = mass * (3 * r * r + length * length) / 12
        return (side, side, mass * r * r / 2)

    def support(self, link_pose: np.ndarray, direction: np.ndarray) -> float:
        """How far the shape reaches along the unit `direction`: the largest p . direction
        over its points p, with the shape on a link at `link_pose`."""
        pose = link_pose @ self.origin.matrix()
        local = pose[:3, :3].T @ direction  # the direction in the shape's own axes
        centre = float(pose[:3, 3] @ direction)
        if self.kind == "mesh":
            return centre + float((self.points @ local).max())
        d = np.abs(local)
        if self.kind == "box":
            return centre + float(d @ np.asarray(self.size))
        if self.kind == "sphere":
            return centre + self.size[0]
        r, half = self.size
        across = 1.0 if self.kind == "capsule" else float(np.sqrt(max(0.0, 1.0 - d[2] * d[2])))
        return centre + half * float(d[2]) + r * across

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """The (low, high) corners of the box along the link's axes that holds the shape."""
        axes = np.eye(3)
        return (np.array([-self.support(np.eye(4), -a) for a in axes]),
                np.array([self.support(np.eye(4), a) for a in axes]))


@dataclass(frozen=True)
class Servo:
    """A joint's position/velocity servo: stiffness kp (N m/rad or N/m) and damping kv."""

    kp: float
    """Stiffness: N m/rad for a revolute joint, N/m for a prismatic one."""
    kv: float
    """Damping: N m s/rad or N s/m."""


@dataclass(frozen=True)
class Joint:
    name: str
    """Unique among the robot's joints; the arm's are listed in `RobotDescription.arm_joints`."""
    kind: Literal["revolute", "prismatic"]
    """revolute (radians) or prismatic (metres)."""
    axis: Vec3
    """Unit axis in the joint's (= child link's) frame."""
    lower: float
    """Lower position limit, rad or m."""
    upper: float
    """Upper position limit, rad or m."""
    velocity: float
    """Speed limit, rad/s or m/s."""
    effort: float
    """Torque or force limit, N m or N."""
    servo: Servo
    """The position/velocity servo that drives it."""
    damping: float = 0.0
    """Viscous damping, N m s/rad or N s/m."""
    armature: float = 0.0
    """Reflected rotor inertia, kg m^2 (kg for prismatic)."""
    friction: float = 0.0
    """Dry friction, N m or N: a self-locking drive resists being pushed back."""


@dataclass(frozen=True)
class Link:
    """A rigid body. `joint` None means it is welded to its parent."""

    name: str
    """Unique among the robot's links."""
    parent: str | None
    """The link it hangs from; None for the fixed base (the first link)."""
    origin: Origin
    """Pose of the link's (and its joint's) frame in the parent link's frame."""
    mass: float
    """kg."""
    shapes: tuple[Shape, ...] = ()
    """Collision primitives, in the link frame; the engines also draw them where `visuals` is empty."""
    joint: Joint | None = None
    """The joint that moves it relative to its parent; None: welded to it."""
    com: Vec3 | None = None
    """Centre of mass in the link frame; None: the centre of the first shape."""
    inertia: Vec3 | None = None
    """Moments (ixx, iyy, izz) about the centre of mass along the link axes, kg m^2;
    None: the first shape as a solid."""
    inertia_products: Vec3 = (0.0, 0.0, 0.0)
    """Products (ixy, ixz, iyz) of the same tensor, kg m^2 (as URDF and MJCF's fullinertia write them)."""
    visuals: tuple[Shape, ...] = ()
    """What the engines draw in place of `shapes` (a URDF's detailed visual meshes), in the link
    frame: no contact, no mass. Empty: the collision shapes are drawn."""

    @property
    def centre_of_mass(self) -> Vec3:
        if self.com is not None:
            return self.com
        return self.shapes[0].origin.xyz if self.shapes else (0.0, 0.0, 0.0)

    @property
    def inertia_diagonal(self) -> Vec3:
        """Moments along the link axes; a rotated first shape is handled through its rotation."""
        if self.inertia is not None:
            return self.inertia
        if not self.shapes:
            i = 1e-5 * max(self.mass, 1e-3)
            return (i, i, i)
        shape = self.shapes[0]
        r = rotation_rpy(shape.origin.rpy)
        full = r @ np.diag(shape.inertia(self.mass)) @ r.T
        return tuple(float(v) for v in np.diag(full))  # type: ignore[return-value]


@dataclass(frozen=True)
class Site:
    """A frame of interest on a link (TCP, wrist sensor, IR sensor, attachment)."""

    name: str
    """How sensors and controllers refer to it (tcp, wrist_ft, ...)."""
    link: str
    """The link it is fixed to."""
    origin: Origin = Origin()
    """Its pose in that link's frame."""


# How much better rubber-covered pads and fingertips grip than an object's own friction (on a
# table) says: rubber on wood, cardboard or plastic 0.6-0.9 against 0.3-0.45 for those on a
# table (engineering tables' typical figures, assumed, not measured on these hands).
RUBBER = 2.0


@dataclass(frozen=True)
class FingerPad:
    """A tactile pad: a thin box on a finger whose +z face is the sensing surface.

    `half_size` = (x, y) half extents of the surface, `taxels` = (rows along y, cols
    along x) of its sensor array, or None where only one force is measured.
    """

    name: str
    """The tactile sensor's name, as the factory's `Sensor` and conditions use it."""
    link: str
    """The finger link it lies on."""
    origin: Origin
    """Pose of the sensing surface's centre in the link frame; +z points out of the finger."""
    half_size: tuple[float, float]
    """(x, y) half extents of the sensing surface, m."""
    thickness: float
    """m; the pad is a thin box behind the surface."""
    taxels: tuple[int, int] | None
    """(rows along y, cols along x) of its sensor array, or None where one force is measured."""

    @property
    def corners(self) -> np.ndarray:
        """The sensing surface's four corners, (4, 4) homogeneous rows, in the surface's frame."""
        return rectangle_corners(self.half_size)


@dataclass(frozen=True)
class HandDof:
    """One actuated motion: the joints it drives, each with its ratio to the DOF value.

    `geared`: the first joint carries the motor and the others follow it through a
    linkage (a Barrett finger's distal joint), so under a force command only the first
    is pushed; otherwise every joint is pushed alike and they move as one (the two jaws of
    a parallel gripper on one spindle; `Hand.couplings`).
    """

    name: str
    """How the hand controllers name this motion."""
    joints: tuple[tuple[str, float], ...]
    """(joint name, ratio to the DOF value) for each joint it drives."""
    closing: int
    """+1 / -1: the direction that closes the hand; 0: it does not close it (a spread)."""
    open: float
    """DOF value fully open."""
    closed: float
    """DOF value fully closed."""
    geared: bool = False
    """True: the first joint carries the motor and the others follow through a linkage."""


@dataclass(frozen=True)
class Hand:
    name: str
    """Short name of the hand model."""
    dofs: tuple[HandDof, ...]
    """Its actuated motions, in the order hand commands list them."""
    pads: tuple[FingerPad, ...]
    """Its tactile pads."""
    postures: dict[str, tuple[float, ...]] = field(default_factory=dict)
    """D5 hand shape (or 'push') -> DOF values; a grasp shape is where the fingers aim to close to."""
    pad_force_from_effort: bool = False
    """True where there is no tactile array: a pad's force is the finger's measured effort."""
    test_grasp: str = "power_grasp"
    """The hand shape (with its preshape) `atd robots test` lifts a 5 cm box with."""
    grasp_centres: dict[str, Vec3] = field(default_factory=dict)
    """Hand shapes that close elsewhere than on the TCP -> where they close, hand frame, from
    the TCP (a pinch between two fingers that stand off the palm centre)."""
    rising_grasps: frozenset[str] = frozenset()
    """Hand shapes whose fingertips are left to rise off the support as they close: the
    sliding grasp only backs off the surface, never follows it down (`follow_surface`)."""
    side_edge_pinch: bool = False
    """Its pinch reopens and moves across when both pads press the object with their side
    edges only (`side_edge_correction`): measured on the SDH2, whose wide pads feel a body
    standing beside them there and lost it in the lift (docs/robust-grasp.md)."""
    push_posture: str = "closed"
    """The posture a closed hand takes to move and push (not a D5 shape): a hand whose fist
    meets an object with sloping links names one that leads with a vertical face."""
    surface_friction: float = 1.0
    """How much better the hand's surfaces (pads, fingers, palm) grip than the object's own
    friction says: a contact's friction is the object's times this, in both engines (MuJoCo
    by explicit contact pairs, Bullet by its product); 1 = the object's friction alone."""
    side_roll: float = 0.0
    """Radians the hand turns about its approach axis, beyond the task's turn, wherever the
    task turns it to grasp from the side: a hand whose pinch closes along its x axis (which
    such a turn stands upright) rolls so that its fingers close across a standing object."""
    pinch_clearance: float = 0.0
    """How far over a task's pinch depth the pads' lower edge stands (m): a hand whose pads
    meet a cap tip first, their faces turned up, loses the cap out of its pinch once the cap's
    lower edge has risen past the tips (a thread's rise between pinches, the arm back at its height)."""
    boxed: dict[str, str] = field(default_factory=dict)
    """Postures the hand makes in place of these in a task that knows a container (a box
    round's reach and grasp): a narrower stand-in for one whose fingers reach past a box's
    walls (the Barrett's pinch preshape spans 28 cm with its flat third finger 16 cm out)."""

    @property
    def couplings(self) -> tuple[tuple[str, str, float], ...]:
        """(joint, other joint, ratio): joints one motor closes together through a rigid
        transmission, `other` = ratio x `joint`: every closing DOF but a geared one (the
        others, a spread, only ever hold a position, which keeps their joints together).
        A gripper's jaws on one spindle cannot drift sideways together; left independent in
        simulation they do, object and all (docs/constants.md)."""
        return tuple((dof.joints[0][0], joint, ratio / dof.joints[0][1])
                     for dof in self.dofs if dof.closing and not dof.geared for joint, ratio in dof.joints[1:])


@dataclass(frozen=True)
class SensorModel:
    """How a sensor differs from the truth: white noise, constant bias, a first-order
    low-pass filter (cutoff in Hz, None = unfiltered) and quantisation (0 = none).
    Noise and bias are one number for every axis or one per axis (force then torque)."""

    noise_std: float | tuple[float, ...] = 0.0
    """Standard deviation of white noise: one for every axis, or one per axis (force, then torque)."""
    bias: float | tuple[float, ...] = 0.0
    """Constant offset, one for every axis or one per axis."""
    cutoff_hz: float | None = None
    """First-order low-pass cutoff, Hz; None: unfiltered."""
    resolution: float = 0.0
    """Quantisation step; 0: none."""


@dataclass(frozen=True)
class DepthCamera:
    """A depth camera fixed in the world, looking at the work area (the thesis's Kinect over
    the table). Its frame is the optical one: z along the view, x to the image's right, y down
    it. A pixel reads the depth along z (m), 0 where nothing lies between `near` and `far`."""

    name: str
    """How primitives ask for its picture (`Robot.capture`)."""
    origin: Origin
    """Pose of its optical frame in the ATD world frame."""
    width: int = 160
    """Pixels across."""
    height: int = 120
    """Pixels down."""
    fovy: float = 43.0
    """Vertical field of view, degrees (square pixels: the horizontal one follows)."""
    near: float = 0.4
    """Nearest depth it reads, m."""
    far: float = 3.5
    """Farthest depth it reads, m."""
    noise: float = 0.0
    """Depth noise: its standard deviation is `noise` times the depth squared (1/m)."""

    @property
    def intrinsics(self) -> tuple[float, float, float, float]:
        """(fx, fy, cx, cy) in pixels, pixel centres at whole numbers from the top left."""
        focal = self.height / 2 / float(np.tan(np.radians(self.fovy) / 2))
        return (focal, focal, (self.width - 1) / 2, (self.height - 1) / 2)


def looking_at(eye: Vec3, target: Vec3) -> Origin:
    """The optical frame at `eye` that looks at `target`, the image's top towards world +z."""
    view = np.subtract(target, eye, dtype=float)
    view /= np.linalg.norm(view)
    right = np.cross(view, (0.0, 0.0, 1.0))
    right /= np.linalg.norm(right)
    return Origin(tuple(float(v) for v in eye), rpy_of(np.column_stack([right, np.cross(view, right), view])))


#: The thesis's Kinect (v1, near mode, sampled down from 640 x 480): over the far side of the
#: table, looking down at the work area from about 0.85 m. Its random depth error grows with
#: the square of the depth, to about 4 cm at 5 m (Khoshelham and Elberink 2012): 1.6e-3 / m.
KINECT = DepthCamera("kinect", looking_at((0.45, 0.0, 0.8), (0.15, 0.0, 0.0)), noise=1.6e-3)


@dataclass(frozen=True)
class RobotDescription:
    name: str
    """The robot's name, as its factory's `name`."""
    arm: str | None
    """Which arm of a two-arm robot; None for one-arm robots."""
    links: tuple[Link, ...]
    """Every link, parents before children; the first is the fixed base."""
    arm_joints: tuple[str, ...]
    """The arm's joint names, base to flange: what arm controllers move."""
    hand_root: str
    """First hand link: its weld to the arm is where the wrist force-torque sensor measures."""
    hand: Hand
    """The hand: its DOFs, pads and postures."""
    tcp: Site
    """The tool centre point: where task positions are reached, z along the approach."""
    wrist_sensor: Site
    """The wrist force-torque frame, on `hand_root`, oriented like the hand frame."""
    base: Origin
    """Placement of the base link in the ATD world frame (origin on the table, x away from the robot)."""
    home: tuple[float, ...]
    """Arm joint positions at the start of every run, one per `arm_joints`."""
    sensors: dict[str, SensorModel] = field(default_factory=dict)
    """How each sensor kind (joints, wrench, tactile, range) differs from the truth."""
    range_sensor: Site | None = None
    """Site of an IR range sensor, if the robot has one."""
    payload: float | None = None
    """Kg the arm may carry at its flange, as published (robot-facts.md); None: not checked."""
    range_limits: tuple[float, float] = (0.0, 0.0)
    """(min, max) distance the range sensor measures, m."""
    extra_sites: tuple[Site, ...] = ()
    """Other frames of interest (attachment points)."""
    control_period: float = 0.005
    """Seconds between control ticks."""
    timestep: float = 0.001
    """Physics step, s."""
    cameras: tuple[DepthCamera, ...] = (KINECT,)
    """Depth cameras it sees the world through; by default the Kinect over the table, which
    every robot at this table shares."""
    park: Vec3 | None = None
    """Where this arm's TCP waits (world, the hand pointing down with its home yaw) while
    another arm of the robot works over the middle of the work area; None: one arm only."""

    @property
    def label(self) -> str:
        return f"{self.name}/{self.arm}" if self.arm else self.name

    @cached_property
    def links_by_name(self) -> dict[str, Link]:
        return {link.name: link for link in self.links}

    @cached_property
    def joints(self) -> dict[str, Joint]:
        """Every joint by name, in tree order."""
        return {link.joint.name: link.joint for link in self.links if link.joint is not None}

    @cached_property
    def joint_link(self) -> dict[str, str]:
        """The link each joint moves."""
        return {link.joint.name: link.name for link in self.links if link.joint is not None}

    @cached_property
    def hand_links(self) -> tuple[str, ...]:
        """hand_root and everything below it."""
        names = [self.hand_root]
        for link in self.links:
            if link.parent in names:
                names.append(link.name)
        return tuple(names)

    @property
    def hand_mass(self) -> float:
        return sum(self.links_by_name[n].mass for n in self.hand_links)

    @property
    def sites(self) -> tuple[Site, ...]:
        found = (self.tcp, self.wrist_sensor) + ((self.range_sensor,) if self.range_sensor else ())
        return found + self.extra_sites

    def hand_joint_targets(self, dof_values: np.ndarray) -> dict[str, float]:
        """Joint positions that put the hand DOFs at `dof_values`."""
        return {
            joint: ratio * float(value)
            for dof, value in zip(self.hand.dofs, dof_values)
            for joint, ratio in dof.joints
        }

    def link_poses(self, joints: dict[str, float]) -> dict[str, np.ndarray]:
        """Forward kinematics: world pose of every link for the given joint positions (missing = 0)."""
        poses: dict[str, np.ndarray] = {}
        for link in self.links:
            parent = poses[link.parent] if link.parent else self.base.matrix()
            pose = parent @ link.origin.matrix()
            if link.joint is not None:
                q = joints.get(link.joint.name, 0.0)
                motion = np.eye(4)
                axis = np.asarray(link.joint.axis, float)
                if link.joint.kind == "revolute":
                    motion[:3, :3] = axis_rotation(axis, q)
                else:
                    motion[:3, 3] = axis * q
                pose = pose @ motion
            poses[link.name] = pose
        return poses

    def site_pose(self, site: Site, joints: dict[str, float]) -> np.ndarray:
        return self.link_poses(joints)[site.link] @ site.origin.matrix()

    def _hand_in(self, posture: str | np.ndarray) -> tuple[dict[str, np.ndarray], np.ndarray]:
        """The links' world poses and the TCP's with the hand in a posture (its name, or its DOF values)."""
        dofs = self.hand.postures[posture] if isinstance(posture, str) else posture
        poses = self.link_poses(self.hand_joint_targets(np.asarray(dofs, float)))
        return poses, poses[self.tcp.link] @ self.tcp.origin.matrix()

    def hand_reach(self, posture: str | np.ndarray) -> float:
        """How far the hand's links reach past the TCP along the approach axis (hand z) in a
        posture (its name, or its DOF values): about 0 when the fingertips end at the TCP,
        negative when the hand ends short of it (a closed fist), so a hand pointing down has
        its lowest point that far below the TCP. The thin tactile pads lie on the links and
        are left out."""
        poses, tcp = self._hand_in(posture)
        approach = tcp[:3, 2]
        farthest = max(shape.support(poses[name], approach)
                       for name in self.hand_links for shape in self.links_by_name[name].shapes)
        return farthest - float(tcp[:3, 3] @ approach)

    def touch_reach(self, posture: str | np.ndarray) -> float:
        """`hand_reach` with the tactile pads' sensing surfaces counted: how far past the TCP
        what a touch leads with reaches, where a pad stands past its link's end (the
        Barrett's pads own the last 4 mm of its fingertips: left out, its pointing finger
        found a cap's top 4 mm high, docs/unscrew-campaign.md)."""
        pads = [float((pad.corners @ surface.T)[:, 2].max()) for pad, surface in zip(self.hand.pads, self._pad_poses(posture))]
        return max([self.hand_reach(posture), *pads])

    def hand_extent(self, posture: str | np.ndarray, within: float | None = None) -> tuple[float, float]:
        """How far the hand's links reach sideways from the TCP's axis in a posture (its name,
        or its DOF values), along the hand's x and along its y, each the further of its two
        sides (`hand_sides`): a parallel jaw opens along one, so a hand pointing down can come
        nearer a wall with the other towards it. With `within` (m), only the links reaching to
        within that of the hand's lowest point, pointing down: its tip, the part a hand sweeping
        low over a floor meets objects with (the Melfa's fingers, not the gripper body 6 cm above them)."""
        plus_x, minus_x, plus_y, minus_y = self.hand_sides(posture, within)
        return max(plus_x, minus_x), max(plus_y, minus_y)

    def hand_sides(self, posture: str | np.ndarray, within: float | None = None) -> tuple[float, float, float, float]:
        """How far the hand's links reach from the TCP's axis in a posture towards the hand's
        +x, -x, +y and -y (m; `within` as `hand_extent`): the SDH2's pinch reaches 8.9 cm
        towards its thumb and 5.0 cm the other way."""
        poses, tcp = self._hand_in(posture)
        approach = tcp[:3, 2]
        shapes = [(poses[name], shape) for name in self.hand_links for shape in self.links_by_name[name].shapes]
        if within is not None:
            lowest = max(shape.support(pose, approach) for pose, shape in shapes)
            shapes = [(pose, shape) for pose, shape in shapes if shape.support(pose, approach) >= lowest - within]

        def reach(way: np.ndarray) -> float:
            return max(shape.support(pose, way) - float(tcp[:3, 3] @ way) for pose, shape in shapes)

        return reach(tcp[:3, 0]), reach(-tcp[:3, 0]), reach(tcp[:3, 1]), reach(-tcp[:3, 1])

    def low_tips(self, posture: str, within: float, about: tuple[float, float] = (0.0, 0.0)
                 ) -> tuple[tuple[float, float], tuple[float, float, float]]:
        """Where the hand's links within `within` of its lowest point, pointing down, stand in a
        posture about the point `about` (hand x y from the TCP: where its fingers close along the
        hand's y): those reaching past the pads' half opening along the y (the closing fingers'
        tips), how far along the y and either way along the x; the others (the SDH2's thumb, 8.9
        cm out along -x), from and to along the x and either way along the y. Zeros where none."""
        poses, tcp = self._hand_in(posture)
        approach, centre = tcp[:3, 2], tcp[:3, 3] + tcp[:3, :2] @ np.asarray(about, float)
        shapes = [(poses[name], shape) for name in self.hand_links for shape in self.links_by_name[name].shapes]
        lowest = max(shape.support(pose, approach) for pose, shape in shapes)
        low = [(pose, shape) for pose, shape in shapes if shape.support(pose, approach) >= lowest - within]
        inner = self.pad_opening(posture, np.pi / 2) / 2.0

        def reach(part: tuple[np.ndarray, Shape], way: np.ndarray) -> float:
            return part[1].support(part[0], way) - float(centre @ way)

        x, y = tcp[:3, 0], tcp[:3, 1]
        closing = [part for part in low if max(reach(part, y), reach(part, -y)) > inner]
        others = [part for part in low if max(reach(part, y), reach(part, -y)) <= inner]
        tips = ((max(reach(part, way) for part in closing for way in (y, -y)),
                 max(reach(part, way) for part in closing for way in (x, -x))) if closing else (0.0, 0.0))
        rest = ((-max(reach(part, -x) for part in others), max(reach(part, x) for part in others),
                 max(reach(part, way) for part in others for way in (y, -y))) if others else (0.0, 0.0, 0.0))
        return tips, rest

    def hand_footprint(self, posture: str | np.ndarray, about: tuple[float, float] = (0.0, 0.0)
                       ) -> tuple[tuple[float, float], tuple[float, float]]:
        """The rectangle the hand covers from above in a posture (`hand_sides`): how far it
        reaches either way from its middle along the hand's x and y, and where that middle lies
        from the point `about` (hand x y from the TCP: where a grasp closes)."""
        plus_x, minus_x, plus_y, minus_y = self.hand_sides(posture)
        extent = ((plus_x + minus_x) / 2, (plus_y + minus_y) / 2)
        return extent, ((plus_x - minus_x) / 2 - about[0], (plus_y - minus_y) / 2 - about[1])

    def tip_length(self, posture: str | np.ndarray, within: float) -> float:
        """How far up from the hand's lowest point, pointing down, its links reach sideways no
        further than its tip (`hand_extent` with `within`) does: how deep below a wall's top the
        hand may go beside it as near as its tip lets (the Melfa's fingers, under its gripper
        body); the whole hand's length where it is no wider anywhere."""
        poses, tcp = self._hand_in(posture)
        approach = tcp[:3, 2]
        shapes = [(poses[name], shape) for name in self.hand_links for shape in self.links_by_name[name].shapes]
        lowest = max(shape.support(pose, approach) for pose, shape in shapes)
        tip = self.hand_extent(posture, within)

        def wider(pose: np.ndarray, shape: Shape) -> bool:
            return any(shape.support(pose, sign * tcp[:3, axis]) - sign * float(tcp[:3, 3] @ tcp[:3, axis])
                       > tip[axis] + 1e-9 for axis in (0, 1) for sign in (1, -1))

        wide = [lowest - shape.support(pose, approach) for pose, shape in shapes if wider(pose, shape)]
        return min(wide, default=lowest + max(shape.support(pose, -approach) for pose, shape in shapes))

    def hand_radius(self, posture: str | np.ndarray) -> float:
        """How far the hand's links reach sideways from the TCP's axis in a posture, the
        furthest along the hand's x and y: what a hand pointing down must keep from a wall it
        moves beside whichever way it turns (the perceive primitive's `hand_radius`)."""
        return max(self.hand_extent(posture))

    def closing_swing(self, start: str, end: str, steps: int = 20) -> float:
        """How much further than in posture `start` the hand reaches along the approach axis
        on its way to posture `end` (m, at least 0): closing fingertips that swing down on
        the way press on the table a hand lowered onto it in `start`."""
        a, b = (np.asarray(self.hand.postures[p], float) for p in (start, end))
        reach = self.hand_reach(a)
        return max(0.0, max(self.hand_reach(a + t * (b - a)) for t in np.linspace(0.0, 1.0, steps + 1)) - reach)

    def closing_line(self, start: str, end: str) -> float | None:
        """The line (rad from the hand's x, about its approach axis, in [0, pi)) along which
        the tactile pads close from posture `start` to posture `end`: the main direction of
        their sideways motion. None where they close from all round (no direction carries
        CLEAR_LINE times another's motion) or do not move: such a hand grasps alike at any turn."""
        if not self.hand.pads:
            return None
        sideways = self._pads_across(end) - self._pads_across(start)
        spread, axes = np.linalg.eigh(sideways.T @ sideways)
        if spread[1] <= 0.0 or spread[1] < CLEAR_LINE * spread[0]:
            return None
        return float(np.arctan2(axes[1, 1], axes[0, 1]) % np.pi)

    def pad_opening(self, posture: str, line: float) -> float:
        """How far apart the tactile pads' surfaces stand along the line at `line` (rad from
        the hand's x, about its approach axis) in `posture` (m): the widest object a hand
        closing along that line from that posture can take between its pads."""
        if not self.hand.pads:
            return 0.0
        along = self._pads_across(posture) @ np.array([np.cos(line), np.sin(line)])
        return float(along.max() - along.min())

    def pinch_reach(self, start: str, end: str, width: float) -> float | None:
        """How far the lower edge of the pads that close from posture `start` to `end` reaches
        past the TCP along the approach axis (as `hand_reach`) where their surfaces first come
        `width` apart along their closing line (corner to corner: a curled finger meets a cap
        with its pad's tip), the hand sweeping the DOFs that differ between the two from open
        to closed: a Barrett's pad tips sweep down and curl back up as they close (2 mm under
        its TCP at 60 mm apart, 12 mm over it at 30 mm), a gripper's jaws keep their height.
        None where the pads do not close along a line."""
        line = self.closing_line(start, end)
        if line is None:
            return None
        a, b = (np.asarray(self.hand.postures[p], float) for p in (start, end))
        moving = np.array([dof.closing != 0 for dof in self.hand.dofs]) & ~np.isclose(a, b)
        opened = np.where(moving, [dof.open for dof in self.hand.dofs], a)
        closed = np.where(moving, [dof.closed for dof in self.hand.dofs], a)
        still = np.isclose(self._pad_poses(a), self._pad_poses(b)).all(axis=(1, 2))
        pads = [k for k in range(len(self.hand.pads)) if not still[k]]
        way = np.array([np.cos(line), np.sin(line), 0.0, 0.0])
        centres = self._pad_poses(opened)[pads, :, 3] @ way
        side = np.sign(centres - centres.mean())  # kept while the sweep goes on: closed fingers cross
        # A finger's other closing DOF flexes back by what the grasp closes, its pad keeping the
        # slant it had in `start`, as the unscrew's hand keeps it (`UnscrewHand._square`).
        closing = np.array([dof.closing for dof in self.hand.dofs], float)
        followers = [(i, k) for p in pads for i in self.moving_dofs(self.hand.pads[p].link) if moving[i]
                     for k in self.moving_dofs(self.hand.pads[p].link) if not moving[k] and closing[k]]

        def corners(t: float) -> list[np.ndarray]:
            q = opened + t * (closed - opened)
            for i, k in followers:
                q[k] = a[k] - closing[k] * closing[i] * (q[i] - a[i])
            surfaces = self._pad_poses(q)
            return [self.hand.pads[k].corners @ surfaces[k].T for k in pads]

        def gap(t: float) -> float:
            inner = [float((c @ way).min() if s > 0 else (c @ way).max()) for c, s in zip(corners(t), side)]
            return min(i for i, s in zip(inner, side) if s > 0) - max(i for i, s in zip(inner, side) if s < 0)

        steps = np.linspace(0.0, 1.0, PINCH_STEPS + 1)
        past = next((k for k, t in enumerate(steps) if gap(t) <= width), None)
        if past is None or past == 0:
            t = 1.0 if past is None else 0.0
        else:  # halve the step the width lies in
            lo, hi = steps[past - 1], steps[past]
            for _ in range(PINCH_HALVINGS):
                lo, hi = (lo, (lo + hi) / 2) if gap((lo + hi) / 2) <= width else ((lo + hi) / 2, hi)
            t = hi
        return max(float(c[:, 2].max()) for c in corners(t))

    def moving_dofs(self, link: str) -> tuple[int, ...]:
        """The hand DOFs with a joint between the hand root and `link`."""
        joints = set()
        while link and link != self.hand_root:
            body = self.links_by_name[link]
            if body.joint is not None:
                joints.add(body.joint.name)
            link = body.parent
        return tuple(k for k, dof in enumerate(self.hand.dofs) if any(j in joints for j, _ in dof.joints))

    def _pads_across(self, posture: str) -> np.ndarray:
        """Where each tactile pad stands across the approach axis in `posture`: (pads, 2), m,
        x y in the hand's frame (its TCP)."""
        return self._pad_poses(posture)[:, :2, 3]

    def _pad_poses(self, posture: str | np.ndarray) -> np.ndarray:
        """Each tactile pad's sensing surface in `posture`: (pads, 4, 4), in the hand's frame (its TCP)."""
        poses, tcp = self._hand_in(posture)
        to_hand = np.linalg.inv(tcp)
        return np.array([to_hand @ poses[p.link] @ p.origin.matrix() for p in self.hand.pads])

    def hand_in_boxes(self, posture: str, tcp: np.ndarray, boxes: list[tuple[Vec3, Vec3]]) -> dict[int, list[str]]:
        """Which of the world-aligned `boxes` (centre, size) the hand's links would cut into
        with its TCP at the pose `tcp` (4x4, world) and its fingers in `posture`: box index ->
        the links that would.

        A link and a box are apart when some axis separates them: the world axes (the box's
        own) or the link shape's axes. The edge-by-edge axes of a full separating-axis test
        are left out, so a link passing a box's edge at a slant may count as cutting it by
        a few millimetres; a hand that close to an obstacle has no room to close anyway."""
        poses = self.link_poses(self.hand_joint_targets(np.asarray(self.hand.postures[posture], float)))
        to_world = tcp @ np.linalg.inv(poses[self.tcp.link] @ self.tcp.origin.matrix())
        placed = [(name, shape, to_world @ poses[name]) for name in self.hand_links
                  for shape in self.links_by_name[name].shapes]
        hit: dict[int, list[str]] = {}
        for k, (centre, size) in enumerate(boxes):
            centre, half = np.asarray(centre, float), np.asarray(size, float) / 2
            for name, shape, pose in placed:
                axes = [*np.eye(3), *(pose @ shape.origin.matrix())[:3, :3].T]
                if name not in hit.get(k, ()) and not any(
                        shape.support(pose, d) <= centre @ d - half @ np.abs(d)
                        or -shape.support(pose, -d) >= centre @ d + half @ np.abs(d) for d in axes):
                    hit.setdefault(k, []).append(name)
        return hit

    def hand_below(self, posture: str, tcp: np.ndarray, height: float) -> tuple[float, list[str]]:
        """How low the hand reaches (world z) with its TCP at the pose `tcp` (4x4, world) and
        its fingers in `posture`, and which of its links reach below `height`."""
        poses = self.link_poses(self.hand_joint_targets(np.asarray(self.hand.postures[posture], float)))
        to_world = tcp @ np.linalg.inv(poses[self.tcp.link] @ self.tcp.origin.matrix())
        down = np.array([0.0, 0.0, -1.0])
        lows = {name: -max(shape.support(to_world @ poses[name], down) for shape in self.links_by_name[name].shapes)
                for name in self.hand_links if self.links_by_name[name].shapes}
        return min(lows.values()), [name for name, low in lows.items() if low < height]

    def tcp_pose(self, arm_q: np.ndarray, hand_dofs: np.ndarray | None = None) -> np.ndarray:
        joints = dict(zip(self.arm_joints, (float(v) for v in arm_q)))
        if hand_dofs is not None:
            joints.update(self.hand_joint_targets(hand_dofs))
        return self.site_pose(self.tcp, joints)

    def tcp_jacobian(self, arm_q: np.ndarray) -> np.ndarray:
        """(6, n) geometric Jacobian of the TCP in the world frame, from this description alone."""
        joints = dict(zip(self.arm_joints, (float(v) for v in arm_q)))
        poses = self.link_poses(joints)
        tcp = (poses[self.tcp.link] @ self.tcp.origin.matrix())[:3, 3]
        columns = []
        for name in self.arm_joints:
            pose = poses[self.joint_link[name]]
            joint = self.joints[name]
            axis = pose[:3, :3] @ np.asarray(joint.axis, float)
            if joint.kind == "revolute":
                columns.append(np.concatenate([np.cross(axis, tcp - pose[:3, 3]), axis]))
            else:
                columns.append(np.concatenate([axis, np.zeros(3)]))
        return np.array(columns).T

    def inverse_kinematics(
        self, target: np.ndarray, start: np.ndarray, iterations: int = 300, tolerance: float = 1e-5
    ) -> tuple[np.ndarray, float]:
        """Arm joints that put the TCP at the 4x4 `target`, by damped least squares within
        the joint limits; returns them with the remaining position error (m)."""
        lower = np.array([self.joints[n].lower for n in self.arm_joints])
        upper = np.array([self.joints[n].upper for n in self.arm_joints])
        q = np.clip(np.asarray(start, float), lower, upper)
        error = np.inf
        for _ in range(iterations):
            pose = self.tcp_pose(q)
            rot_err = 0.5 * sum(np.cross(pose[:3, i], target[:3, i]) for i in range(3))
            e = np.concatenate([target[:3, 3] - pose[:3, 3], rot_err])
            error = float(np.linalg.norm(e[:3]))
            if np.linalg.norm(e) < tolerance:
                break
            jac = self.tcp_jacobian(q)
            step = jac.T @ np.linalg.solve(jac @ jac.T + 1e-4 * np.eye(6), e)
            q = np.clip(q + step, lower, upper)
        return q, error
