"""The arbitrator's merge rules, including its pass-through of a single controller."""

from __future__ import annotations

import numpy as np

from atd.runtime.arbitrator import arbitrate
from primitives.base import ArmCommand, ControlData, HandCommand
from primitives.robot import HandMode

P, V, F = HandMode.POSITION, HandMode.VELOCITY, HandMode.FORCE


def test_one_arm_controller_s_twist_is_the_command() -> None:
    twist = np.array([0.1, 0.0, -0.2, 0.0, 0.3, 0.0])
    command = arbitrate([ControlData(arm=ArmCommand(twist=twist))], hand_dof=1)
    np.testing.assert_array_equal(command.twist, twist)
    assert command.joint_velocity is None and command.hand_values is None


def test_twists_blend_by_weight_and_joint_velocities_separately() -> None:
    outputs = [
        ControlData(arm=ArmCommand(twist=np.array([0.3, 0, 0, 0, 0, 0]), weight=1.0)),
        ControlData(arm=ArmCommand(twist=np.array([0, 0.3, 0, 0, 0, 0]), weight=2.0)),
        ControlData(arm=ArmCommand(joint_velocity=np.array([0.0, 0.5]))),
    ]
    command = arbitrate(outputs, hand_dof=1)
    np.testing.assert_allclose(command.twist, [0.1, 0.2, 0, 0, 0, 0])
    np.testing.assert_allclose(command.joint_velocity, [0.0, 0.5])


def test_a_contribution_without_weight_moves_nothing() -> None:
    command = arbitrate([ControlData(arm=ArmCommand(twist=np.ones(6), weight=0.0))], hand_dof=1)
    assert command.twist is None


def test_one_hand_controller_driving_every_dof_passes_through_as_a_copy() -> None:
    values = np.array([0.1, 0.2, 0.3])
    command = arbitrate([ControlData(hand=HandCommand(values=values, modes=(P, F, V)))], hand_dof=3)
    np.testing.assert_array_equal(command.hand_values, values)
    assert command.hand_modes == (P, F, V)
    values[0] = 9.0  # the controller reusing its array does not change the command already sent
    assert command.hand_values[0] == 0.1


def test_per_hand_dof_the_heaviest_wins_and_undriven_dofs_stand_still() -> None:
    outputs = [
        ControlData(hand=HandCommand(values=np.array([1.0, 1.0, np.nan]), modes=(P, P, P), weight=1.0)),
        ControlData(hand=HandCommand(values=np.array([np.nan, 2.0, np.nan]), modes=(F, F, F), weight=2.0)),
    ]
    command = arbitrate(outputs, hand_dof=3)
    np.testing.assert_array_equal(command.hand_values, [1.0, 2.0, 0.0])
    assert command.hand_modes == (P, F, V)


def test_a_hand_nobody_drives_gets_no_command() -> None:
    nothing = ControlData(hand=HandCommand(values=np.full(2, np.nan), modes=(P, P)))
    assert arbitrate([nothing], hand_dof=2).hand_values is None
    assert arbitrate([], hand_dof=2).hand_values is None
