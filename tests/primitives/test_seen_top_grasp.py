"""A jaw coming down on the top a perceive state saw (thesis 3.4.3's rounds): the look landed
on the object and said its top, but the approach lay off the object's middle, and one jaw, or
both, met that top. Half the blind exploration rounds of the preset ended so, each paying a
whole look (15-48 s) again (docs/empty-the-box.md). The grasp now moves the jaws halfway to
the jaw that met it, and turns them a quarter turn where that is not enough, within the round."""

from __future__ import annotations

import numpy as np
import pytest

from atd.api import load, translate
from primitives.perception.container import approach_pose
from primitives.values import Approach
from tests.conftest import REPO
from tests.primitives.box_worlds import BELIEF, FLOOR, MELFA_REACH, box_world, cube
from tests.primitives.conftest import events, execute

TASK = REPO / "tests" / "data" / "empty_the_box" / "grasp_on_seen_top.xml"
MIDDLE = (0.18, 0.15)  # the box's middle (tests.primitives.box_worlds)
HEIGHT = 0.045  # m: a block lying as the wood block does


@pytest.mark.parametrize("size, off", [
    ((0.06, 0.05), 0.022),  # 5 cm across the jaws, its middle 2.2 cm off the hand's axis: one jaw on its top
    ((0.04, 0.075), 0.0),  # 7.5 cm across the jaws, longer than they open (6.8 cm): both jaws on its top
], ids=["under_one_jaw", "longer_than_the_jaws_open"])
def test_a_grasp_whose_jaw_came_down_on_the_seen_top_holds_the_block_within_the_round(size, off) -> None:
    """The Melfa's approach over a block's top, the jaws closing along the box's y, told the top
    (as blind exploration tells it): without the half move and the turn the grasp ended "a jaw
    met something with the fingertips at the seen top" in both cases (its move across went the
    whole way to the jaw, and the other jaw came down on the top; nothing turned the jaws)."""
    task = load(TASK)
    robot = box_world(cube("block", MIDDLE, size=size, height=HEIGHT))
    top = FLOOR + HEIGHT
    point = np.array([MIDDLE[0], MIDDLE[1] - off, top])
    approach = Approach(approach_pose(BELIEF, point, MELFA_REACH, 0.02), point, "blind_exploration", top=top)
    outcome, executor = execute(translate(task, "melfa"), robot, task=task, memory={"approach": approach})
    robot.close()
    reasons = [c.get("reason") for e in events(executor) for c in e["conditions"] if c.get("reason")]
    assert outcome.end_state == "held", (outcome.summary, reasons)
    entered = {e["state"]: e["t"] for e in executor.trace.records if e["type"] == "enter"}
    assert outcome.sim_time - entered["grasp"] < 15.0  # under the shortest look
