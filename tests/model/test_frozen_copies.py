"""A model copied with new field values answers from the new values, never from indexes
cached on the original (a campaign's perturbed ESTD once ran the unperturbed states)."""

from __future__ import annotations

from atd.model import load_task
from factories.registry import create
from tests.conftest import REPO
from translator import translate


def test_an_estd_copied_with_new_states_indexes_the_new_states() -> None:
    task, _ = load_task(REPO / "examples" / "grasp_and_lift.xml")
    estd = translate(task, create("melfa")).estd
    assert estd.states_by_name["approach"].arm.params["target"] == (0.1, 0.0, 0.18)  # the index is cached now
    moved = tuple(s.model_copy(update={"arm": s.arm.model_copy(update={"params": {**s.arm.params,
                                                                               "target": (0.2, 0.0, 0.18)}})})
                  if s.name == "approach" else s for s in estd.states)
    copy = estd.model_copy(update={"states": moved})
    assert copy.states_by_name["approach"].arm.params["target"] == (0.2, 0.0, 0.18)
    assert copy.leaving == estd.leaving
    assert estd.states_by_name["approach"].arm.params["target"] == (0.1, 0.0, 0.18)


def test_a_task_copied_with_new_states_indexes_the_new_states() -> None:
    task, _ = load_task(REPO / "examples" / "grasp_and_lift.xml")
    assert "approach" in task.states_by_name
    fewer = task.model_copy(update={"states": tuple(s for s in task.states if s.name != "approach")})
    assert "approach" not in fewer.states_by_name
