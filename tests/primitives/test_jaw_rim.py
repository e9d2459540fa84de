"""Jaws that close on nothing after a finger's bare rim pushed the object (the pads feel
nothing there, so they say no side) look first on the side the wrist felt the push: the
torque about the approach axis over the push across the jaws is where along their width it
was (generalisation.toml: the object 4 cm along the jaws' width, spun away by the rim)."""

from __future__ import annotations

import numpy as np
import pytest

from atd.model.estd import Controller
from atd.sim import load_description
from atd.sim.simrobot import robot_info
from primitives.base import Context
from primitives.registry import build_controller
from primitives.robot import Readings

MELFA = robot_info(load_description("melfa"))
DOWN = np.diag([1.0, -1.0, -1.0])  # the hand pointing down, its x (the jaws' width) along the world's x


def _at(position: tuple[float, float, float], wrench: tuple[float, ...] = (0.0,) * 6) -> Readings:
    """The Melfa's TCP still at `position`, the wrist reading `wrench` (hand axes), pads feeling nothing."""
    tcp = np.eye(4)
    tcp[:3, :3], tcp[:3, 3] = DOWN, position
    zeros = np.zeros(6)
    return Readings(time=0.0, arm_q=zeros, arm_dq=zeros, arm_effort=zeros, hand_q=np.array([0.03]),
                    hand_dq=np.zeros(1), hand_effort=np.zeros(1), tcp=tcp, wrench=np.array(wrench, float),
                    taxels={}, pad_force=np.zeros(2), range=None)


def _first_search_way(lever: float | None) -> float:
    """Close beside an object, a finger pushing it 3 N across the jaws at `lever` m along their
    width (None: nothing pushed), the jaws closing on nothing: which way along the jaws'
    width (world x) the arm then heads to look."""
    ctx = Context(info=MELFA, params={}, environment=None)
    arm = build_controller(Controller(name="jaw_grasp_correction", params={}), "arm", ctx)
    period = MELFA.control_period
    arm.start(_at((0.4, 0.0, 0.08)))
    for _ in range(20):  # risen clear: the descent starts
        arm.update(_at((0.4, 0.0, 0.10)), period)
    for _ in range(5):  # down at the grasp height without a contact: the jaws close
        arm.update(_at((0.4, 0.0, 0.02)), period)
    assert ctx.blackboard.contact
    push = (0.0,) * 6 if lever is None else (0.0, 3.0, 0.0, 0.0, 0.0, 3.0 * lever)
    for _ in range(40):
        arm.update(_at((0.4, 0.0, 0.02), push), period)
    ctx.blackboard.jaws_empty = True
    arm.update(_at((0.4, 0.0, 0.02)), period)
    ctx.blackboard.jaws_empty = False
    way = 0.0
    for _ in range(60):  # at the top of the rise: the move across begins
        way = float(arm.update(_at((0.4, 0.0, 0.04)), period).arm.twist[0])
    return way


@pytest.mark.parametrize("lever", (-0.02, 0.02))
def test_jaws_closing_on_nothing_after_a_rim_pushed_the_object_look_on_that_side_first(lever: float) -> None:
    assert np.sign(_first_search_way(lever)) == np.sign(lever)


def test_without_a_push_the_search_looks_where_its_plan_says() -> None:
    assert _first_search_way(None) > 0.0  # the plan's first point: +search_step along the jaws' width
