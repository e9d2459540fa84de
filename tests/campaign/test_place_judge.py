"""The place judge measures where the task puts the object down, whatever point of the hand
the robot's TCP is."""

from __future__ import annotations

import numpy as np

from atd.campaign.cells import plans
from atd.campaign.record import TrialRecord
from atd.campaign.trial import _judge, trial_run
from atd.campaign.spec import load_spec
from tests.conftest import REPO

SPEC = REPO / "examples" / "campaigns" / "pick_and_place_displaced.toml"


def test_the_sdh2s_pick_and_place_is_judged_at_the_tasks_target_not_at_its_tcps() -> None:
    """The SDH2 pinches 19 mm off its TCP, so its ESTD sends the TCP to (0.119, 0.10): judged
    there, a box set down on the task's (0.10, 0.10) was 1.9 cm off, and one 1.9 cm off was on it."""
    loaded, found = load_spec(SPEC)
    assert loaded is not None, found
    plan = next(iter(plans(loaded, {"robot": {"tombatossals"}, "arm": {"left"}, "engine": {"mujoco"}}, 1)))
    run, belief = trial_run(plan, TrialRecord(cell=plan.cell, index=plan.index, seed=plan.seed))
    try:
        judge = _judge(plan, belief, run)
    finally:
        run.robot.close()
    (place,) = [s for s in belief.states if s.name == "put_down"]
    assert np.allclose(judge.target[:2], (0.10, 0.10)), judge.target
    assert not np.allclose(place.arm.params["target"][:2], (0.10, 0.10))  # the TCP's target is elsewhere
