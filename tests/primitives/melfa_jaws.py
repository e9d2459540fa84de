"""A scripted Melfa for the jaw grasp's tests: readings with its hand held still, and a jaw
grasp correction brought to where its jaws are told to close, so each test scripts only
what the pads and the wrist feel after that."""

from __future__ import annotations

from typing import Callable

import numpy as np

from atd.model.estd import Controller
from atd.sim import load_description
from atd.sim.simrobot import robot_info
from primitives.base import Context
from primitives.registry import build_controller
from primitives.robot import Readings

MELFA = robot_info(load_description("melfa"))
DOWN = np.diag([1.0, -1.0, -1.0])  # the hand pointing down, its x (the jaws' width) along the world's x
GRASP_HEIGHT = (0.4, 0.0, 0.02)  # m: where the scripted grasp closes its jaws

Position = tuple[float, float, float]


def still(position: Position = GRASP_HEIGHT, wrench: tuple[float, ...] = (0.0,) * 6, q: float = 0.03,
          pads: tuple[float, float] = (0.0, 0.0), taxels: dict[str, np.ndarray] | None = None) -> Readings:
    """The Melfa still: its TCP at `position` pointing down, the wrist reading `wrench` (hand
    axes), its jaws at `q`, the pads pressing `pads` N with `taxels` images."""
    tcp = np.eye(4)
    tcp[:3, :3], tcp[:3, 3] = DOWN, position
    zeros = np.zeros(6)
    return Readings(time=0.0, arm_q=zeros, arm_dq=zeros, arm_effort=zeros, hand_q=np.array([q]),
                    hand_dq=np.zeros(1), hand_effort=np.zeros(1), tcp=tcp, wrench=np.array(wrench, float),
                    taxels=taxels or {}, pad_force=np.array(pads, float), range=None)


def closing_correction(at: Callable[[Position], Readings] = still) -> tuple[Context, Controller]:
    """A jaw grasp correction started 8 cm up, risen clear, then at the grasp height without a
    contact: its jaws have just been told to close (`blackboard.contact`)."""
    ctx = Context(info=MELFA, params={}, environment=None)
    arm = build_controller(Controller(name="jaw_grasp_correction", params={}), "arm", ctx)
    period = MELFA.control_period
    arm.start(at((0.4, 0.0, 0.08)))
    for _ in range(20):  # risen clear: the descent starts
        arm.update(at((0.4, 0.0, 0.10)), period)
    for _ in range(5):  # down at the grasp height without a contact: the jaws close
        arm.update(at(GRASP_HEIGHT), period)
    assert ctx.blackboard.contact
    return ctx, arm
