"""What a robot knows of itself (`RobotInfo`), from its description: limits, the hand's
DOFs, pads, servo stiffness, and the hand's model behind the wrist sensor (mass, centre of
mass), as a real hand's datasheet and kinematics give them.

Built from the factory's description, this is the controllers' belief (`Factory.info`);
the simulator builds its robot from the description of the truth, which a campaign may
perturb, and the controllers never see that one.
"""

from __future__ import annotations

import numpy as np

from factories.description import RobotDescription
from primitives.robot import HandInfo, PadInfo, RobotInfo


def _tcp_pose(d: RobotDescription, poses: dict[str, np.ndarray]) -> np.ndarray:
    """The TCP's pose among link `poses` from the description's forward kinematics."""
    return poses[d.tcp.link] @ d.tcp.origin.matrix()


def _finger_base(d: RobotDescription, link: str, poses: dict[str, np.ndarray]) -> tuple[float, float]:
    """Where the finger carrying `link` stands on the palm: its first link's origin, (x, y)
    in the hand (TCP) frame; the palm's own pads stand where they are."""
    while link != d.hand_root and d.links_by_name[link].parent != d.hand_root:
        link = d.links_by_name[link].parent
    tcp = _tcp_pose(d, poses)
    x, y, _ = tcp[:3, :3].T @ (poses[link][:3, 3] - tcp[:3, 3])
    return (float(x), float(y))


def _pad_surfaces(d: RobotDescription):
    """The hand's forward kinematics for its pads: DOF values -> each sensing surface's
    pose in the TCP frame (only the hand's joints move one against the other)."""

    def surfaces(q: np.ndarray) -> np.ndarray:
        poses = d.link_poses(d.hand_joint_targets(q))
        to_hand = np.linalg.inv(_tcp_pose(d, poses))
        return np.array([to_hand @ poses[p.link] @ p.origin.matrix() for p in d.hand.pads])

    return surfaces


def _centre_of_mass(d: RobotDescription):
    """The hand's model behind the wrist sensor: DOF values -> its centre of mass, TCP frame."""
    links = [d.links_by_name[n] for n in d.hand_links]
    masses = np.array([link.mass for link in links])

    def centre(q: np.ndarray) -> np.ndarray:
        poses = d.link_poses(d.hand_joint_targets(q))
        points = np.array([poses[link.name] @ np.array([*link.centre_of_mass, 1.0]) for link in links])
        return (np.linalg.inv(_tcp_pose(d, poses)) @ (masses @ points / masses.sum()))[:3]

    return centre


def _wrist(d: RobotDescription, poses: dict[str, np.ndarray]) -> np.ndarray:
    """The wrist sensor's origin in the TCP frame (both ride on the palm)."""
    return (np.linalg.inv(_tcp_pose(d, poses)) @ poses[d.wrist_sensor.link] @ d.wrist_sensor.origin.matrix())[:3, 3]


def robot_info(d: RobotDescription) -> RobotInfo:
    """The static facts a primitive needs, taken from the description."""
    arm = [d.joints[n] for n in d.arm_joints]
    hand_limits = [d.joints[dof.joints[0][0]] for dof in d.hand.dofs]
    ratios = np.array([abs(dof.joints[0][1]) for dof in d.hand.dofs])
    open_hand = d.link_poses(d.hand_joint_targets(np.array([dof.open for dof in d.hand.dofs])))
    lower = np.array([min(j.lower / r, j.upper / r) for j, r in zip(hand_limits, ratios)])
    upper = np.array([max(j.lower / r, j.upper / r) for j, r in zip(hand_limits, ratios)])
    hand = HandInfo(
        dofs=tuple(dof.name for dof in d.hand.dofs),
        lower=lower,
        upper=upper,
        velocity_limit=np.array([j.velocity for j in hand_limits]) / ratios,
        effort_limit=np.array([j.effort for j in hand_limits]) * ratios,
        closing=np.array([dof.closing for dof in d.hand.dofs], float),
        open=np.array([dof.open for dof in d.hand.dofs]),
        closed=np.array([dof.closed for dof in d.hand.dofs]),
        postures={name: np.array(v) for name, v in d.hand.postures.items()},
        pads=tuple(PadInfo(p.name, p.taxels, d.moving_dofs(p.link), _finger_base(d, p.link, open_hand), p.half_size)
                   for p in d.hand.pads),
        stiffness=np.array([j.servo.kp for j in hand_limits]) * ratios**2,
        self_locking=np.array([j.friction > 0 for j in hand_limits]),
        pad_surfaces=_pad_surfaces(d),
        mass=d.hand_mass,
        centre_of_mass=_centre_of_mass(d),
        wrist=_wrist(d, open_hand),
        surface_friction=d.hand.surface_friction,
    )
    return RobotInfo(
        name=d.label,
        control_period=d.control_period,
        arm_joints=d.arm_joints,
        arm_lower=np.array([j.lower for j in arm]),
        arm_upper=np.array([j.upper for j in arm]),
        arm_velocity_limit=np.array([j.velocity for j in arm]),
        arm_effort_limit=np.array([j.effort for j in arm]),
        home=np.array(d.home, float),
        hand=hand,
        has_range=d.range_sensor is not None,
        range_limits=d.range_limits,
        cameras=tuple(c.name for c in d.cameras),
    )
