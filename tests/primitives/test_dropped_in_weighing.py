"""A bunny that slipped out of the Barrett's pinch as the arm lifted it to weigh it is grasped
again where it stood: at the shipped generalisation seed 8117 (left_near, trial 2) the pads
lost it 13 mm up, it dropped back where it stood, and the hand, reading that as a push aside,
closed next 4.5 cm off it, at the lifted height, and searched until the grasp's 20 s ran out
(docs/robust-grasp.md, "The bunny dropped in the weighing")."""

from __future__ import annotations

from pathlib import Path

from tests.primitives.conftest import campaign_trial, generalisation_at


def test_a_bunny_dropped_in_the_weighing_is_grasped_again_where_it_stood(tmp_path: Path) -> None:
    record = campaign_trial(generalisation_at(8117, tmp_path), 2, "robot=tombatossals", "arm=right",
                            "engine=mujoco", "perturbation=approach", "task=left_near", "object=bunny")
    grasped = [why for event in record.events if event["transition"] == "grasp_object->lift_object"
               for why in event["why"] if why.startswith("object held after")]
    assert grasped, record.events
    assert record.judged_succeeded, (record.judge_reason, record.summary)
