"""MuJoCo's sensors are worked out once a control period, on its last physics step, the only
one whose values are read; the physics and every reading stay as they were, bit for bit."""

from __future__ import annotations

from dataclasses import fields
from typing import Mapping

import mujoco
import numpy as np

from atd.sim.selftest import close_on_box, move_tcp, pose
from primitives.robot import Readings

SENSORS_OFF = int(mujoco.mjtDisableBit.mjDSBL_SENSOR)


def _flat(readings: Readings) -> bytes:
    """Every value of a reading, as bytes: equal only when each float is the same."""
    parts = []
    for f in fields(readings):
        value = getattr(readings, f.name)
        values = [value[k] for k in sorted(value)] if isinstance(value, Mapping) else [value]
        parts += [np.asarray(np.nan if v is None else v, float).tobytes() for v in values]
    return b"".join(parts)


def _gripping(robot, monkeypatch, always_sensing: bool) -> tuple[list[bytes], list[bool]]:
    """Grip the scene's box and lift it (pads pressed, the wrist loaded), reading every period;
    with `always_sensing`, every physics step works the sensors out, as it did before."""
    real, sensed = mujoco.mj_step, []

    def step(m, d):
        if always_sensing:
            m.opt.disableflags &= ~SENSORS_OFF
        sensed.append(not m.opt.disableflags & SENSORS_OFF)
        real(m, d)

    monkeypatch.setattr(mujoco, "mj_step", step)
    seen = []

    def tick():
        robot.step()
        seen.append(_flat(robot.read()))

    orientation = robot.read().tcp[:3, :3]
    close_on_box(robot, orientation, tick)
    move_tcp(robot, pose(orientation, robot.object_pose()[:3, 3] + (0, 0, 0.05)), tick, speed=0.1)
    seen.append(robot.data.qpos.tobytes() + robot.data.qvel.tobytes())
    monkeypatch.setattr(mujoco, "mj_step", real)
    return seen, sensed


def test_sensors_once_a_period_read_as_before(melfa, robot_of, monkeypatch) -> None:
    robot = robot_of(melfa, "mujoco")
    substeps = robot.substeps
    assert substeps > 1
    now, sensed = _gripping(robot, monkeypatch, always_sensing=False)
    before, _ = _gripping(robot_of(melfa, "mujoco"), monkeypatch, always_sensing=True)
    assert len(now) == len(before) > 300
    assert now == before  # every reading of every period, and the state at the end
    assert robot.read().pad_force.min() > 1.0  # both pads pressed
    steps = np.array(sensed).reshape(-1, substeps)
    assert steps[:, -1].all() and not steps[:, :-1].any()
    assert robot.model.opt.disableflags & SENSORS_OFF == 0  # left as the model had it
