"""Several arms of one robot in one world, for tasks that name roles: what both engines share.

A robot description is one arm with its hand (`description(arm)` of its factory), and each
carries the robot's trunk (Baxter's torso and pedestal) in the same place; an engine builds
each arm as it builds one (MuJoCo: atd/sim/mujoco_arms.py; PyBullet: a body per arm) and
lets the arms pass through one another, so the trunks only overlap. Every arm's home puts
its hand over the middle of the work area (docs/robots.md), so an added arm starts
`parked` where its description says an idle arm waits (`park`).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from atd.sim.scene import SceneError
from factories.description import RobotDescription

PARK_TOLERANCE = 0.002  # m the inverse kinematics may leave the parked hand from where it is asked


def parked(arm: RobotDescription) -> RobotDescription:
    """`arm` with its home moved to where its description parks an idle arm (`park`): its hand
    top-down with its home yaw, out of the way of the arm that works from home (SceneError
    where the description parks none or the arm cannot get there)."""
    if arm.park is None:
        raise SceneError(f"the {arm.label}'s description says nowhere for it to wait while another arm works "
                         "(RobotDescription.park): it would start in the other arm's way")
    home = np.array(arm.home, float)
    target = arm.tcp_pose(home)
    target[:3, 3] = arm.park
    q, error = arm.inverse_kinematics(target, home)
    if error > PARK_TOLERANCE:
        raise SceneError(f"the {arm.label} cannot park its hand at ({', '.join(f'{v:g}' for v in arm.park)}), "
                         f"where its description parks it (the nearest is {error * 1000:.0f} mm off): it would "
                         "start in the other arm's way")
    return dataclasses.replace(arm, home=tuple(round(float(v), 6) for v in q))
