"""The checks behind `atd robots test`: is a simulated robot fit to run tasks?

Each check drives the robot through the robot interface only (as a primitive would) and
measures the outcome from the engine's true state. Thresholds are those of issue 4.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from atd.model.frames import GRAVITY
from atd.sim import installed_engines, make_robot
from atd.sim.scene import Scene, box_scene
from atd.sim.simrobot import SimRobot
from factories.description import RobotDescription
from primitives.robot import HandMode, Robot

FK_TOLERANCE = 1e-3  # m
HOLD_TOLERANCE = 1e-3  # m of TCP drift
LIFT = 0.10  # m
HOLD_TIME = 3.0  # s
SLIP_TOLERANCE = 0.01  # m
WEIGHT_TOLERANCE = 0.10  # relative
# Peak joint speed over the limit while every joint runs to its limits at once: the
# command is clamped to the limit, the servos overshoot it briefly under the coupling.
SPEED_TOLERANCE = 0.25  # relative
GRIP_FRACTION = 0.4  # of each closing DOF's effort limit
BOX = 0.05  # m

Recorder = Callable[[SimRobot], None]


@dataclass(frozen=True)
class Check:
    name: str
    passed: bool
    measured: str


def run_all(d: RobotDescription, engine: str, seed: int = 0, record: Recorder | None = None) -> list[Check]:
    """Every check, each on a fresh robot."""
    hold, at_rest, free_tactile = check_at_rest(d, engine, seed)
    grasp, grasp_tactile = check_grasp(d, engine, seed, record)
    return [check_kinematics(d, engine, seed), check_limits(d, engine, seed), hold, at_rest, grasp, free_tactile, grasp_tactile]


def check_kinematics(d: RobotDescription, engine: str, seed: int) -> Check:
    """Engine TCP vs the description's own forward kinematics, and the engines vs each other
    where both are installed."""
    robots = {e: make_robot(d, Scene(None, table=False), e, seed) for e in dict.fromkeys((engine, *installed_engines()))}
    rng = np.random.default_rng(seed)
    info = robots[engine].info
    centre, half = (info.arm_upper + info.arm_lower) / 2, (info.arm_upper - info.arm_lower) / 2
    worst_desc = worst_pair = 0.0
    try:
        for q in [info.home] + [centre + 0.8 * half * rng.uniform(-1, 1, info.arm_dof) for _ in range(6)]:
            expected = d.tcp_pose(q, info.hand.open)[:3, 3]
            tcp = {}
            for name, robot in robots.items():
                robot.reset_arm(q)
                tcp[name] = robot.read().tcp[:3, 3]
            worst_desc = max(worst_desc, float(np.linalg.norm(tcp[engine] - expected)))
            worst_pair = max(worst_pair, max(float(np.linalg.norm(tcp[e] - tcp[engine])) for e in tcp))
    finally:
        for robot in robots.values():
            robot.close()
    return Check(
        "forward kinematics",
        worst_desc < FK_TOLERANCE and worst_pair < FK_TOLERANCE,
        f"TCP off by {worst_desc * 1000:.3f} mm from the description, "
        + (f"engines {worst_pair * 1000:.3f} mm apart" if len(robots) > 1 else "one engine installed")
        + " (7 poses)",
    )


def check_limits(d: RobotDescription, engine: str, seed: int) -> Check:
    """Drive every joint at twice its speed limit to each end: it must get there at no more
    than its speed limit and stop at the limit."""
    robot = make_robot(d, Scene(None, table=False), engine, seed)
    info = robot.info
    hand = info.hand
    period = info.control_period
    problems = []
    peak = 0.0
    try:
        for sign in (1.0, -1.0):
            goal = info.arm_upper if sign > 0 else info.arm_lower
            hand_goal = hand.upper if sign > 0 else hand.lower
            robot.command_arm_velocity(sign * 2 * info.arm_velocity_limit)
            robot.command_hand(hand_goal, HandMode.POSITION)
            span = float(np.max((info.arm_upper - info.arm_lower) / info.arm_velocity_limit))
            fastest = np.zeros(info.arm_dof)  # this direction's peak speeds
            beyond = np.zeros(info.arm_dof)
            for _ in range(int((span + 1.0) / period)):
                robot.step()
                r = robot.read()
                fastest = np.maximum(fastest, np.abs(r.arm_dq))
                beyond = np.maximum(beyond, np.maximum(r.arm_q - info.arm_upper, info.arm_lower - r.arm_q))
            r = robot.read()
            peak = max(peak, float(np.max(fastest / info.arm_velocity_limit)))
            for i, name in enumerate(info.arm_joints):
                if abs(r.arm_q[i] - goal[i]) > 0.02:
                    problems.append(f"{name} stopped {r.arm_q[i] - goal[i]:+.3f} from its limit")
                if beyond[i] > 0.01:
                    problems.append(f"{name} passed its limit by {beyond[i]:.3f}")
                if fastest[i] > (1 + SPEED_TOLERANCE) * info.arm_velocity_limit[i]:
                    problems.append(f"{name} ran at {fastest[i]:.2f} > {info.arm_velocity_limit[i]:.2f}")
            for i, name in enumerate(hand.dofs):
                tolerance = 0.02 * (hand.upper[i] - hand.lower[i])
                if abs(r.hand_q[i] - hand_goal[i]) > tolerance:
                    problems.append(f"hand {name} stopped {r.hand_q[i] - hand_goal[i]:+.4f} from its limit")
    finally:
        robot.close()
    joints = info.arm_dof + len(hand.dofs)
    return Check("joint limits", not problems, "; ".join(problems) or f"{joints} joints reach both limits; peak speed {peak:.0%} of the limit")


def check_at_rest(d: RobotDescription, engine: str, seed: int) -> tuple[Check, Check, Check]:
    """Hold the home pose for 2 s: TCP drift, wrist reading vs the hand's weight, silent pads."""
    robot = make_robot(d, box_scene(BOX), engine, seed)
    info = robot.info
    expected = d.tcp_pose(info.home, info.hand.open)[:3, 3]
    drift = 0.0
    wrench = []
    touch = 0.0
    try:
        robot.command_arm_velocity(np.zeros(info.arm_dof))
        for i in range(int(2.0 / info.control_period)):
            robot.step()
            r = robot.read()
            drift = max(drift, float(np.linalg.norm(r.tcp[:3, 3] - expected)))
            wrench.append(r.wrench)
            touch = max(touch, float(r.pad_force.max(initial=0.0)), _taxel_max(r.taxels))
    finally:
        robot.close()
    weight = d.hand_mass * GRAVITY
    fz = float(np.mean([w[2] for w in wrench[len(wrench) // 2 :]]))
    return (
        Check("holds pose against gravity", drift < HOLD_TOLERANCE, f"TCP within {drift * 1000:.2f} mm of home over 2 s"),
        Check(
            "F/T at rest = hand weight",
            abs(fz - weight) <= WEIGHT_TOLERANCE * weight,
            f"fz {fz:.2f} N vs {weight:.2f} N ({(fz / weight - 1) * 100:+.1f}%)",
        ),
        Check("tactile zero in free space", touch == 0.0, f"largest pad reading {touch:.3f} N"),
    )


def check_grasp(d: RobotDescription, engine: str, seed: int, record: Recorder | None = None) -> tuple[Check, Check]:
    """Scripted, non-reactive: preshape, descend top-down, close with a fixed force, lift 10 cm, hold 3 s.

    The hand makes its `test_grasp` shape; every pad on a finger that shape moves must feel the box.
    """
    robot = make_robot(d, box_scene(BOX), engine, seed)
    info = robot.info
    hand = info.hand

    def tick() -> None:
        robot.step()
        if record is not None:
            record(robot)

    try:
        box = robot.object_pose()[:3, 3]
        orientation = d.tcp_pose(info.home, hand.open)[:3, :3]
        _, modes = close_on_box(robot, orientation, tick)
        r = robot.read()
        pads = r.pad_force.copy()
        taxel_ok = all(img is None or img.sum() > 0 for img, f in zip(r.taxels.values(), pads) if f > 0)
        touching = _pads_moved(d, [dof for dof, m in zip(d.hand.dofs, modes) if m == HandMode.FORCE])
        start = robot.object_pose()[2, 3]
        move_tcp(robot, pose(orientation, box + (0, 0, LIFT)), tick, speed=0.1)
        lifted = robot.object_pose()[2, 3] - start
        held = np.linalg.inv(robot.read().tcp) @ robot.object_pose()
        robot.command_arm_velocity(np.zeros(info.arm_dof))
        for _ in range(int(HOLD_TIME / info.control_period)):
            tick()
        after = np.linalg.inv(robot.read().tcp) @ robot.object_pose()
        slip = float(np.linalg.norm(after[:3, 3] - held[:3, 3]))
    finally:
        robot.close()
    names = [p.name for p in hand.pads]
    return (
        Check(
            "grasp lifts 5 cm box 10 cm, holds 3 s",
            lifted > LIFT - SLIP_TOLERANCE and slip < SLIP_TOLERANCE,
            f"lifted {lifted * 100:.1f} cm, slipped {slip * 1000:.2f} mm in {HOLD_TIME:g} s",
        ),
        Check(
            "tactile non-zero in the grasp",
            bool((pads[touching] > 0).all()) and taxel_ok,
            f"{d.hand.test_grasp}: " + ", ".join(f"{n} {f:.1f} N" for n, f in zip(names, pads)),
        ),
    )


def close_on_box(robot: Robot, orientation: np.ndarray, tick: Callable[[], None]) -> tuple[np.ndarray, list[HandMode]]:
    """The scripted, non-reactive grasp: the hand's `test_grasp` preshape, down onto the
    scene's box from 10 cm above it, then a fixed push for 1 s on the DOFs that the grasp
    posture moves (the others hold). Returns the hand command that holds the box."""
    hand = robot.info.hand
    shape = robot.description.hand.test_grasp
    preshape, grasp = hand.postures[f"{shape}_preshape"], hand.postures[shape]
    box = robot.object_pose()[:3, 3]
    robot.command_hand(preshape, HandMode.POSITION)
    move_tcp(robot, pose(orientation, box + (0, 0, LIFT)), tick)
    move_tcp(robot, pose(orientation, box), tick, speed=0.05)
    moving = (hand.closing != 0) & ~np.isclose(grasp, preshape)
    command = np.where(moving, hand.closing * GRIP_FRACTION * hand.effort_limit, preshape)
    modes = [HandMode.FORCE if m else HandMode.POSITION for m in moving]
    robot.command_hand(command, modes)
    for _ in range(int(1.0 / robot.info.control_period)):
        tick()
    return command, modes


def _pads_moved(d: RobotDescription, dofs) -> np.ndarray:
    """Which pads ride on a finger that one of `dofs` moves (those must feel the object)."""
    driven = {joint for dof in dofs for joint, _ in dof.joints}
    links = d.links_by_name
    moved = []
    for pad in d.hand.pads:
        link, hit = links[pad.link], False
        while link is not None and not hit:
            hit = link.joint is not None and link.joint.name in driven
            link = links.get(link.parent) if link.parent else None
        moved.append(hit)
    return np.array(moved)


def pose(rotation: np.ndarray, position) -> np.ndarray:
    m = np.eye(4)
    m[:3, :3] = rotation
    m[:3, 3] = position
    return m


def move_tcp(robot: Robot, target: np.ndarray, tick: Callable[[], None], speed: float = 0.2, timeout: float = 6.0) -> None:
    """Straight-line Cartesian move by twist commands, as an arm primitive would make it."""
    period = robot.info.control_period
    for _ in range(int(timeout / period)):
        tcp = robot.read().tcp
        error = np.concatenate([target[:3, 3] - tcp[:3, 3], 0.5 * sum(np.cross(tcp[:3, i], target[:3, i]) for i in range(3))])
        if np.linalg.norm(error[:3]) < 2e-4 and np.linalg.norm(error[3:]) < 2e-3:
            break
        twist = 5.0 * error
        norm = np.linalg.norm(twist[:3])
        if norm > speed:
            twist[:3] *= speed / norm
        robot.command_arm_twist(twist)
        tick()
    robot.command_arm_velocity(np.zeros(robot.info.arm_dof))


def _taxel_max(taxels) -> float:
    return max((float(img.max()) for img in taxels.values() if img is not None), default=0.0)
