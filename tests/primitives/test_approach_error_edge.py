"""An approach the arm cannot finish ends the grasp-and-lift through `error`, saying why, as
soon as its move says so: without the edge, a move the approach error put out of reach
(Baxter's left arm stalled 3 cm short, generalisation.toml, base seed 44021) stood until the
task's 20 s timeout."""

from __future__ import annotations

from atd.campaign.perturbation import approach_taken
from atd.model import load_task
from atd.sim import load_description, make_robot
from atd.sim.scene import scene_from_task
from factories.registry import create
from tests.primitives.conftest import EXAMPLES, events, execute, last_reasons
from translator import translate

# the approach error taking the hand 30 cm down, into the table: the free move meets it and stops
INTO_THE_TABLE = {"dx": 0.0, "dy": 0.0, "dz": -0.3, "roll": 0.0, "pitch": 0.0, "yaw": 0.0}


def test_an_approach_that_cannot_finish_ends_through_error_with_its_reason() -> None:
    path = EXAMPLES / "grasp_and_lift.xml"
    task, _ = load_task(path)
    estd = approach_taken(translate(task, create("melfa")).estd, INTO_THE_TABLE)
    robot = make_robot(load_description("melfa"), scene_from_task(task, path))
    outcome, executor = execute(estd, robot, task=task)
    last = events(executor)[-1]
    assert not outcome.succeeded
    assert (last["state"], last["event"]) == ("approach", "error") and last["t"] < 2.0, (last["event"], last["t"])
    assert last_reasons(executor)[0].startswith("unexpected contact"), last_reasons(executor)
