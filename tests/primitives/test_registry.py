"""The registry against the vocabulary: every name an ESTD may use runs, and nothing else."""

from __future__ import annotations

import pytest

from atd.model.controllers import ARM_CONTROLLERS, CONDITIONS, HAND_CONTROLLERS
from atd.model.estd import Condition, Controller
from primitives.base import Context
from primitives.registry import ARM, CONDITION_KINDS, HANDS, BuildError, build_condition, build_controller
from tests.primitives.conftest import melfa


def test_every_vocabulary_name_has_an_implementation_and_nothing_more() -> None:
    assert set(ARM) == set(ARM_CONTROLLERS)
    assert set().union(*HANDS.values()) == set(HAND_CONTROLLERS)
    assert set(CONDITION_KINDS) == set(CONDITIONS)


def test_every_hand_kind_has_the_postures() -> None:
    for kind, table in HANDS.items():
        assert {"hold_position", "hand_shape", "open_to"} <= set(table), kind


@pytest.fixture(scope="module")
def ctx() -> Context:
    return Context(info=melfa().info, params={})


def test_defaults_are_filled_and_the_estd_values_win(ctx: Context) -> None:
    move = build_controller(Controller(name="cartesian_move", params={"target": (0.1, 0.0, 0.1), "max_speed": 0.05}),
                            "arm", ctx)
    assert move.params["force_threshold"] == 15.0  # thesis 3.3.2 default
    assert move.params["max_speed"] == 0.05


@pytest.mark.parametrize(("use", "role", "message"), [
    (Controller(name="hand_shape", params={"shape": "hook_grasp"}), "hand", "cannot make the shape 'hook_grasp'"),
    (Controller(name="robust_grasp_hand", params={"grasp_shape": "power_grasp"}), "hand",
     "has no 'robust_grasp_hand' controller"),
    (Controller(name="squeeze"), "arm", "'squeeze' is not an arm controller"),
])
def test_what_the_robot_cannot_run_is_refused_with_the_reason(ctx: Context, use, role: str, message: str) -> None:
    with pytest.raises(BuildError, match=message):
        build_controller(use, role, ctx)


@pytest.mark.parametrize(("leaf", "message"), [
    (Condition(kind="tactile_force_above", sensors=("tactile_palm",)), "'tactile_palm' names no pad"),
    (Condition(kind="range_below", sensors=("ir_range",)), "has no range sensor"),
])
def test_conditions_on_sensors_the_robot_lacks_are_refused(ctx: Context, leaf: Condition, message: str) -> None:
    with pytest.raises(BuildError, match=message):
        build_condition(leaf, ctx)
