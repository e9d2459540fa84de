"""The robot interface a primitive uses: hand modes, the DLS solver, the static facts."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from atd.model import HandShape
from atd.model.resolved_rate import dls_joint_velocities, limited_joint_velocities
from atd.sim import load_description, variants
from atd.sim.scene import Scene
from primitives.robot import HandMode


@given(st.integers(0, 10_000))
@settings(max_examples=50, deadline=None)
def test_dls_tracks_a_twist_exactly_away_from_singularities(seed: int) -> None:
    rng = np.random.default_rng(seed)
    jacobian = rng.normal(size=(6, 7))
    twist = rng.normal(size=6)
    np.testing.assert_allclose(jacobian @ dls_joint_velocities(jacobian, twist, 0.0), twist, atol=1e-9)


def test_dls_damping_bounds_joint_speed_at_a_singularity() -> None:
    jacobian = np.zeros((6, 6))
    jacobian[:5, :5] = np.eye(5)
    jacobian[5, 5] = 1e-6  # one direction nearly lost
    twist = np.array([0, 0, 0, 0, 0, 0.1])
    assert np.abs(dls_joint_velocities(jacobian, twist, 0.0)).max() > 1e4
    assert np.abs(dls_joint_velocities(jacobian, twist, 0.02)).max() < 1e-2


def test_a_joint_near_its_limit_leaves_a_turn_to_a_joint_that_makes_the_same_one() -> None:
    """A wrist at its singularity: joints 4 and 6 turn the hand about one axis. Far from
    their limits they share the turn; with joint 4 a hair from its upper limit and the turn
    pushing it there, joint 6 makes nearly all of it, and the hand still turns as asked."""
    jacobian = np.zeros((6, 6))
    jacobian[:3, :3] = np.eye(3)
    jacobian[3, 4] = 1.0
    jacobian[5, 3] = jacobian[5, 5] = 1.0  # j4 and j6 about the same axis
    twist = np.array([0, 0, 0, 0, 0, 0.2])
    lower, upper = np.full(6, -2.8), np.full(6, 2.8)
    free = limited_joint_velocities(jacobian, twist, 0.02, np.zeros(6), lower, upper)
    np.testing.assert_allclose(free, dls_joint_velocities(jacobian, twist, 0.02))
    assert free[3] == pytest.approx(free[5])
    q = np.array([0, 0, 0, 2.78, 0, 0])
    spared = limited_joint_velocities(jacobian, twist, 0.02, q, lower, upper)
    assert spared[3] < 0.05 * spared[5]
    np.testing.assert_allclose(jacobian @ spared, twist, atol=0.01)
    back = limited_joint_velocities(jacobian, -twist, 0.02, q, lower, upper)  # away from the limit: no share taken
    assert back[3] == pytest.approx(back[5])


def test_engine_jacobian_matches_the_descriptions(robot_of, engine) -> None:
    for robot, arm in variants():
        d = load_description(robot, arm)
        r = robot_of(d, engine, Scene(None, table=False))
        np.testing.assert_allclose(r.jacobian(), d.tcp_jacobian(np.array(d.home)), atol=2e-3)


def test_hand_position_velocity_and_force_modes(melfa, robot_of, run, engine) -> None:
    robot = robot_of(melfa, engine, Scene(None, table=False))
    robot.command_hand([0.01], HandMode.POSITION)
    run(robot, 1.0)
    assert robot.read().hand_q[0] == pytest.approx(0.01, abs=5e-4)
    robot.command_hand([0.01], HandMode.VELOCITY)  # opening at 1 cm/s
    run(robot, 1.0)
    assert robot.read().hand_q[0] == pytest.approx(0.02, abs=1.5e-3)
    robot.command_hand([-20.0], HandMode.FORCE)  # closes until the jaws meet
    run(robot, 1.0)
    r = robot.read()
    assert r.hand_q[0] == pytest.approx(0.0, abs=1e-3)
    assert r.hand_effort[0] == pytest.approx(-20.0, rel=0.05)


def test_a_hand_command_repeated_every_tick_acts_as_the_executor_expects(melfa, robot_of, engine) -> None:
    """The executor repeats its hand command each tick: a DOF leaving force mode holds where
    it is for that tick, then the repeated position command takes it where it was asked."""
    robot = robot_of(melfa, engine, Scene(None, table=False))

    def repeat(values, mode, seconds: float) -> None:
        for _ in range(round(seconds / robot.info.control_period)):
            robot.command_hand(values, mode)
            robot.step()

    repeat([-20.0], HandMode.FORCE, 0.5)  # jaws shut
    repeat([0.015], HandMode.POSITION, 1.0)
    assert robot.read().hand_q[0] == pytest.approx(0.015, abs=5e-4)


def test_a_hand_velocity_beyond_the_limit_is_clamped(melfa, robot_of, run, engine) -> None:
    robot = robot_of(melfa, engine, Scene(None, table=False))
    start = robot.read().hand_q[0]
    robot.command_hand([-1.0], HandMode.VELOCITY)
    run(robot, 0.2)
    moved = start - robot.read().hand_q[0]
    assert moved == pytest.approx(0.2 * robot.info.hand.velocity_limit[0], rel=0.2)


def test_static_facts_describe_each_hand() -> None:
    for robot, arm in variants():
        info_hand = load_description(robot, arm).hand
        names = set(info_hand.postures)
        assert {"open", "closed"} <= names
        assert info_hand.push_posture in names, f"{robot}: the push posture must be one of the hand's postures"
        shapes, stand_ins = {shape.value for shape in HandShape}, set(info_hand.boxed.values())
        assert names - {info_hand.push_posture} - stand_ins <= shapes, \
            f"{robot}: postures must be D5 hand shapes, the one the hand pushes with, or a shape's stand-in in a box"
        assert set(info_hand.boxed) <= shapes and stand_ins <= names, \
            f"{robot}: a box's stand-in replaces a D5 hand shape with a posture of the hand's"
        for values in info_hand.postures.values():
            assert len(values) == len(info_hand.dofs)
    barrett = load_description("tombatossals", "right").hand
    assert [d.name for d in barrett.dofs] == ["spread", "f1", "f2", "f3"]
    assert "hook_grasp" in barrett.postures
    assert "hook_grasp" not in load_description("tombatossals", "left").hand.postures  # SDH2 cannot (thesis A.1.2)


def test_each_pad_knows_where_its_finger_stands_on_the_palm() -> None:
    """The robust grasp's finger-lost correction shifts towards the fingers that touched;
    where they stand comes from the description (thesis A.1.2's layouts), in the hand frame."""
    from atd.sim.simrobot import robot_info

    def bases(arm: str) -> dict[str, tuple[float, float]]:
        return {p.name: p.base for p in robot_info(load_description("tombatossals", arm)).hand.pads}

    barrett = bases("right")  # F1 and F2 either side of the palm centre, the thumb opposite
    assert barrett["tactile_f1"] == pytest.approx((-0.025, 0.0), abs=1e-9)
    assert barrett["tactile_f2"] == pytest.approx((0.025, 0.0), abs=1e-9)
    assert barrett["tactile_f3"] == pytest.approx((0.0, -0.05), abs=1e-9)
    sdh2 = bases("left")  # two fingers on one side of the rotation axis, the thumb on the other
    assert sdh2["tactile_f1"] == pytest.approx((0.019, 0.033), abs=1e-9)
    assert sdh2["tactile_f2"] == pytest.approx((0.019, -0.033), abs=1e-9)
    assert sdh2["tactile_f3"] == pytest.approx((-0.038, 0.0), abs=1e-9)


def test_the_object_can_be_teleported_or_taken_away(melfa, robot_of, run, engine) -> None:
    """Fault hook for the layers above: the object vanishes from the hand as a real one may slip out."""
    robot = robot_of(melfa, engine)
    away = np.eye(4)
    away[:3, 3] = (0.4, -0.4, 0.025)
    robot.place_object(away)
    run(robot, 0.2)
    np.testing.assert_allclose(robot.object_pose()[:3, 3], away[:3, 3], atol=1e-3)
