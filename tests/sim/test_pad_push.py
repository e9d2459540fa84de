"""A PyBullet pad that pushes an object along the table feels it push, tick after tick.

The Melfa's jaws close on the steel weight standing 1 cm off their middle: the left pad meets
it first and pushes it along the table (0.34 kg, 1.7 N of friction) until the right pad meets
it. PyBullet's jaw servo, stepped to each control period's reference, pushes in one or two of
the period's five physics steps; a pad read at the last step alone said 0 N on most ticks of
the push, and the grasp, feeling nothing, closed on without re-centring (docs/robust-grasp.md,
`pbw33`). MuJoCo's pad, read the same way, felt over 0.5 N on a third of the push's ticks
(not investigated there).
"""

from __future__ import annotations

import numpy as np

from atd.sim.library import get
from atd.sim.scene import Scene
from primitives.robot import HandMode

TOUCH = 0.5  # N on a pad: the jaw grasp's own touch (primitives/hands/parallel_jaw.py)
CLOSING = 0.04  # m/s: the jaw grasp's closing speed
OFF_MIDDLE = 0.01  # m: the weight stands this far towards the left pad (+y)


def test_a_pad_pushing_the_weight_along_the_table_feels_the_push(melfa, robot_of) -> None:
    weight = get("weight")
    start = np.eye(4)
    grip = np.array([0.125, 0.0, 0.035])  # the TCP, pads' middle, 12 mm above the table at their tips
    start[:3, 3] = (grip[0], grip[1] + OFF_MIDDLE, weight.size[1] / 2)
    robot = robot_of(melfa, "pybullet", Scene(weight.body("object", start)))
    target = robot.read().tcp.copy()
    target[:3, 3] = grip
    q, error = melfa.inverse_kinematics(target, robot.read().arm_q)
    assert error < 1e-4
    robot.reset_arm(q)
    robot.hold_still(0.2)
    reference, period = float(robot.read().hand_q[0]), robot.info.control_period
    felt, pushed = [], []
    last = robot.object_pose()[1, 3]
    for _ in range(round(1.0 / period)):
        reference -= CLOSING * period
        robot.command_hand([reference], HandMode.POSITION)
        robot.step()
        forces, y = robot.read().pad_force, robot.object_pose()[1, 3]
        if forces[1] > TOUCH:  # the right pad has met it: a grip, no longer a push
            break
        if last - y > 0.5 * CLOSING * period:  # the weight moved towards the right pad this tick
            pushed.append(last - y)
            felt.append(forces[0])
        last = y
    assert sum(pushed) > 0.005, "the left pad pushed the weight along the table"
    assert np.mean(np.array(felt) > TOUCH) > 0.8, np.round(felt, 2)
