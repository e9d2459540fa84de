"""Jaws that close on nothing after a finger's bare rim pushed the object (the pads feel
nothing there, so they say no side) look first on the side the wrist felt the push: the
torque about the approach axis over the push across the jaws is where along their width it
was (generalisation.toml: the object 4 cm along the jaws' width, spun away by the rim)."""

from __future__ import annotations

import numpy as np
import pytest

from tests.primitives.melfa_jaws import GRASP_HEIGHT, MELFA, closing_correction, still


def _first_search_way(lever: float | None) -> float:
    """Close beside an object, a finger pushing it 3 N across the jaws at `lever` m along their
    width (None: nothing pushed), the jaws closing on nothing: which way along the jaws'
    width (world x) the arm then heads to look."""
    ctx, arm = closing_correction()
    period = MELFA.control_period
    push = (0.0,) * 6 if lever is None else (0.0, 3.0, 0.0, 0.0, 0.0, 3.0 * lever)
    for _ in range(40):
        arm.update(still(GRASP_HEIGHT, push), period)
    ctx.blackboard.jaws_empty = True
    arm.update(still(), period)
    ctx.blackboard.jaws_empty = False
    way = 0.0
    for _ in range(60):  # at the top of the rise: the move across begins
        way = float(arm.update(still((0.4, 0.0, 0.04)), period).arm.twist[0])
    return way


@pytest.mark.parametrize("lever", (-0.02, 0.02))
def test_jaws_closing_on_nothing_after_a_rim_pushed_the_object_look_on_that_side_first(lever: float) -> None:
    assert np.sign(_first_search_way(lever)) == np.sign(lever)


def test_without_a_push_the_search_looks_where_its_plan_says() -> None:
    assert _first_search_way(None) > 0.0  # the plan's first point: +search_step along the jaws' width
