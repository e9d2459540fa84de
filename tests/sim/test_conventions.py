"""Same frames and signs on both engines: what a primitive reads must not depend on the engine."""

from __future__ import annotations

import numpy as np
import pytest

from atd.model.frames import GRAVITY
from atd.sim import ENGINES, load_description, variants
from atd.sim.scene import Scene, box_scene
from primitives.filters import held_wrench
from primitives.robot import HandMode


@pytest.mark.parametrize(("robot", "arm"), variants())
def test_both_engines_put_the_tcp_where_the_description_says(robot, arm, robot_of) -> None:
    d = load_description(robot, arm)
    robots = [robot_of(d, e, Scene(None, table=False)) for e in ENGINES]
    rng = np.random.default_rng(7)
    info = robots[0].info
    for _ in range(5):
        q = rng.uniform(info.arm_lower, info.arm_upper)
        expected = d.tcp_pose(q, info.hand.open)
        for r in robots:
            r.reset_arm(q)
            np.testing.assert_allclose(r.read().tcp, expected, atol=1e-3)


def test_home_is_a_top_down_pose_over_the_work_area() -> None:
    for robot, arm in variants():
        d = load_description(robot, arm)
        tcp = d.tcp_pose(np.array(d.home))
        assert tcp[2, 2] == pytest.approx(-1.0, abs=1e-6), f"{d.label}: hand z must point down"
        np.testing.assert_allclose(tcp[:3, 3], (0.125, 0.0, 0.15), atol=1e-3)


@pytest.mark.parametrize(("robot", "arm"), variants())
def test_every_corner_of_the_work_area_is_reachable_top_down(robot, arm) -> None:
    d = load_description(robot, arm)
    target = d.tcp_pose(np.array(d.home))
    for x in (0.0, 0.25):
        for y in (-0.25, 0.25):
            for z in (0.025, 0.2):
                target[:3, 3] = (x, y, z)
                _, error = d.inverse_kinematics(target, np.array(d.home))
                assert error < 1e-4, f"{d.label} cannot reach ({x}, {y}, {z}) top-down"



def test_the_melfas_wrist_stays_clear_of_its_singularity_over_the_work_areas_floor(melfa) -> None:
    """Top-down at an object's height anywhere on the work area, the Melfa's j5 is well off
    zero, where its forearm and flange rolls turn the hand alike (mounted level with the table,
    j5 was 0 at the middle: rolls swung against each other onto j4's limit)."""
    target = melfa.tcp_pose(np.array(melfa.home))
    for x in (0.0, 0.1, 0.25):
        for y in (-0.25, 0.0, 0.25):
            for z in (0.025, 0.05):
                target[:3, 3] = (x, y, z)
                q, error = melfa.inverse_kinematics(target, np.array(melfa.home))
                assert error < 1e-4 and abs(q[4]) > 0.25, (x, y, z, q[4])


ACCELERATING = 20  # ticks


def test_hand_down_reads_its_weight_and_a_guarded_move_feels_the_table_alike(melfa, robot_of, run) -> None:
    """Common convention: fz ~ +m_hand g hanging; moving down onto the table makes the tared
    fz drop below -5 N (thesis Eq. 3.2) at the height where the fingertips meet the table."""
    fingertip_below_tcp = melfa.hand.pads[0].half_size[1]  # pads end flush with the fingertips
    for engine in ENGINES:
        robot = robot_of(melfa, engine, box_scene(xy=(0.2, 0.2)))
        robot.command_hand([0.0], HandMode.POSITION)
        run(robot, 0.5)
        rest = robot.read().wrench.copy()
        assert rest[2] == pytest.approx(melfa.hand_mass * GRAVITY, rel=0.02), engine
        robot.command_arm_twist(np.array([0, 0, -0.05, 0, 0, 0]))
        for tick in range(800):
            robot.step()
            # The hand's first 0.1 s are its start: pushed from rest to 5 cm/s, it reads as heavier.
            if tick >= ACCELERATING and robot.read().wrench[2] - rest[2] < -5.0:
                break
        r = robot.read()
        assert r.wrench[2] - rest[2] < -5.0, f"{engine}: the table was never felt"
        assert r.tcp[2, 3] == pytest.approx(fingertip_below_tcp, abs=1.5e-3), engine


def test_a_twist_moves_the_tcp_the_same_way_on_both_engines(melfa, robot_of, run) -> None:
    twist = np.array([0.05, -0.03, 0.02, 0.0, 0.0, 0.2])
    moved = []
    for engine in ENGINES:
        robot = robot_of(melfa, engine)
        start = robot.read().tcp.copy()
        robot.command_arm_twist(twist)
        run(robot, 1.0)
        robot.command_arm_velocity(np.zeros(6))
        run(robot, 0.3)
        end = robot.read().tcp
        moved.append(end[:3, 3] - start[:3, 3])
        direction = moved[-1] / np.linalg.norm(moved[-1])
        assert direction @ (twist[:3] / np.linalg.norm(twist[:3])) > 0.99, engine
        turn = end[:3, :3] @ start[:3, :3].T  # rotation done, in the world frame
        yaw = np.arctan2(turn[1, 0], turn[0, 0])
        assert yaw == pytest.approx(0.2, abs=0.03), engine
    np.testing.assert_allclose(moved[0], moved[1], atol=2e-3)


def test_joint_commands_beyond_the_limits_are_clamped(melfa, robot_of, run, engine) -> None:
    robot = robot_of(melfa, engine, Scene(None, table=False))
    info = robot.info
    robot.command_arm_velocity(np.full(info.arm_dof, 100.0))
    peak = np.zeros(info.arm_dof)
    for _ in range(round(4.0 / info.control_period)):
        robot.step()
        peak = np.maximum(peak, np.abs(robot.read().arm_dq))
    q = robot.read().arm_q
    assert np.all(q <= info.arm_upper + 0.01)
    assert np.all(peak <= 1.25 * info.arm_velocity_limit)
    np.testing.assert_allclose(q, info.arm_upper, atol=0.02)


def test_a_tilted_hand_reads_the_same_wrench_on_both_engines(melfa, robot_of, run) -> None:
    """Gravity seen from a tilted hand: force components and the torque of the hand's weight about the sensor."""
    mean = {}
    for engine in ENGINES:
        robot = robot_of(melfa, engine, box_scene(xy=(0.3, 0.3)))
        _tilt_wrist(robot, run)
        run(robot, 0.5)
        samples = []
        for _ in range(100):
            robot.step()
            samples.append(robot.read().wrench)
        mean[engine] = np.mean(samples, axis=0)
    mj, pb = mean["mujoco"], mean["pybullet"]
    assert np.linalg.norm(mj[:3]) == pytest.approx(melfa.hand_mass * GRAVITY, rel=0.01)
    assert abs(mj[0]) > 3 and abs(mj[1]) > 2 and abs(mj[3]) > 0.1  # really tilted: weight on every axis
    np.testing.assert_allclose(mj[:3], pb[:3], atol=0.05)
    np.testing.assert_allclose(mj[3:], pb[3:], atol=0.005)


def _tilt_wrist(robot, run) -> None:
    """Turn the last two arm joints for 1 s, then stop: the hand's weight on every axis."""
    dq = np.zeros(robot.info.arm_dof)
    dq[-2:] = 0.5
    robot.command_arm_velocity(dq)
    run(robot, 1.0)
    robot.command_arm_velocity(np.zeros(robot.info.arm_dof))


@pytest.mark.parametrize(("robot", "arm"), variants())
def test_the_hands_model_explains_its_own_wrist_reading_at_any_posture(robot, arm, robot_of, run) -> None:
    """Gravity compensation: the wrist reading less the hand's own weight, from its model
    (mass and centre of mass from its encoders), is what it holds, nothing in free air."""
    d = load_description(robot, arm)
    for engine in ENGINES:
        r = robot_of(d, engine, Scene(None, table=False))
        hand = r.info.hand
        _tilt_wrist(r, run)
        for posture in (hand.open, hand.closed):
            r.command_hand(posture, HandMode.POSITION)
            run(r, 1.0)
            raw, left = [], []
            for _ in range(100):
                r.step()
                raw.append(r.read().wrench)
                left.append(held_wrench(hand, r.read()))
            raw, left = np.mean(raw, axis=0), np.mean(left, axis=0)
            assert np.linalg.norm(raw[:3]) > 10 * np.linalg.norm(left[:3])  # the hand's weight was there
            assert np.linalg.norm(left[:3]) < 0.3 and np.linalg.norm(left[3:]) < 0.02, (engine, posture, left)


def test_an_arm_meeting_the_table_pushes_like_a_servo_not_a_rigid_motor(melfa, robot_of) -> None:
    """A guarded descent at the robust grasp's 5 mm/s feels the table with a force that builds
    up over the servo's stiffness on both engines. PyBullet's position motor, left rigid up
    to the joint's effort limit, struck it with about 800 N within one tick (MuJoCo: 5 N),
    and a sliding grasp tared at that contact pressed the fingertips on the table for ever."""
    fingertip_below_tcp = melfa.hand.pads[0].half_size[1]
    for engine in ENGINES:
        robot = robot_of(melfa, engine, box_scene(xy=(0.2, 0.2)))
        rest = robot.read().wrench[2]
        robot.command_arm_twist(np.array([0, 0, -0.05, 0, 0, 0]))
        while robot.read().tcp[2, 3] > fingertip_below_tcp + 0.005:
            robot.step()
        robot.command_arm_twist(np.array([0, 0, -0.005, 0, 0, 0]))
        forces: list[float] = []
        while len(forces) < 5:  # from the first tick over 2 N on, 20 ms
            robot.step()
            assert robot.read().time < 10.0, f"{engine}: the table was never felt"
            force = rest - robot.read().wrench[2]
            if forces or force > 2.0:
                forces.append(force)
        assert max(forces) < 50.0, f"{engine}: the table was struck with {max(forces):.0f} N"
