"""Belief and truth kept apart (issue 33): a campaign trial may simulate a hand heavier than
its factory describes, and the controllers still know their robot as the factory describes
it: what they make of the wrist sensor is then off by the weight nobody told them of."""

from __future__ import annotations

import numpy as np
import pytest

from atd.campaign import trial
from atd.campaign.cells import TrialPlan
from atd.campaign.perturbation import HandPhysics
from atd.campaign.record import TASK_OBJECT, Cell, TrialRecord
from atd.model.frames import GRAVITY
from factories.registry import create
from primitives.filters import held_wrench, world_load
from tests.conftest import REPO

TASK = REPO / "examples" / "grasp_and_lift.xml"
HEAVY = HandPhysics(model="hand_physics", mass=(2.0, 2.0), servo=(1.0, 1.0))  # the hand twice as heavy as described


def _plan() -> TrialPlan:
    cell = Cell("grasp_and_lift", "melfa", create("melfa").arm.name, "mujoco", "robust", TASK_OBJECT, "heavy_hand")
    return TrialPlan(cell, 0, 1234, str(TASK), None, HEAVY, 60.0)


def test_the_simulated_hand_is_heavier_and_the_controllers_model_is_the_described_one() -> None:
    plan = _plan()
    record = TrialRecord(cell=plan.cell, index=0, seed=plan.seed)
    run, _ = trial.trial_run(plan, record)
    try:
        believed = create("melfa").robot.hand_mass
        assert record.perturbation == {"hand_mass_scale": 2.0, "servo_scale": 1.0}
        assert run.robot.description.hand_mass == pytest.approx(2 * believed)
        assert run.context.info.hand.mass == pytest.approx(believed)
        run.robot.hold_still(0.3)
        readings = run.robot.read()
        # The wrist sensor weighs the simulated hand: twice the described mass ...
        assert np.linalg.norm(world_load(readings)) / GRAVITY == pytest.approx(2 * believed, rel=0.03)
        # ... so the controllers, compensating the described hand, feel a load of one hand's weight in the empty hand.
        phantom = np.linalg.norm(held_wrench(run.context.info.hand, readings)[:3]) / GRAVITY
        assert phantom == pytest.approx(believed, rel=0.06)
    finally:
        run.robot.close()


def test_every_controller_of_a_campaign_trial_sees_the_believed_hand(monkeypatch) -> None:
    """The whole trial as `atd campaign run` runs it: every controller and condition the
    executor builds, in every state, is built with the factory's hand mass."""
    from atd.runtime import executor

    seen: set[float] = set()
    build_controller, build_condition = executor.build_controller, executor.build_condition

    def controller(use, role, ctx):
        seen.add(ctx.info.hand.mass)
        return build_controller(use, role, ctx)

    def condition(leaf, ctx):
        seen.add(ctx.info.hand.mass)
        return build_condition(leaf, ctx)

    monkeypatch.setattr(executor, "build_controller", controller)
    monkeypatch.setattr(executor, "build_condition", condition)
    record = trial.run_trial(_plan())
    assert record.status == "ok", record.error
    assert record.perturbation["hand_mass_scale"] == 2.0 and len(record.events) >= 2, record.summary
    assert seen == {create("melfa").robot.hand_mass}
