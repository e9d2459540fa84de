"""A bunny that slipped out of the Barrett's pinch as the arm lifted it to weigh it.

At the shipped generalisation seed 8117 (left_near, trial 2) the pads lost it 13 mm up, it
dropped back where it stood, and the hand, reading that as a push aside, closed next 4.5 cm off
it, at the lifted height, and searched until the grasp's 20 s ran out (docs/robust-grasp.md,
"The bunny dropped in the weighing"). At fresh seed 50255 (right_far, trial 1) it was held at
5 N, slipped out 13 mm up, was closed on again where it stood and at 5 N slipped out again
("The Barrett beyond the preset at two fresh seeds")."""

from __future__ import annotations

import re
from pathlib import Path

from atd.campaign.record import TrialRecord
from tests.primitives.conftest import campaign_trial, generalisation_at


def _bunny(seed: int, trial: int, place: str, tmp_path: Path) -> TrialRecord:
    return campaign_trial(generalisation_at(seed, tmp_path), trial, "robot=tombatossals", "arm=right",
                          "engine=mujoco", "perturbation=approach", f"task={place}", "object=bunny")


def _held(record: TrialRecord) -> str:
    """Why the grasp said it held the object (its transition to the lift)."""
    held = [why for event in record.events if event["transition"] == "grasp_object->lift_object"
            for why in event["why"] if why.startswith("object held after")]
    assert held, record.events
    return held[0]


def test_a_bunny_dropped_in_the_weighing_is_grasped_again_where_it_stood(tmp_path: Path) -> None:
    record = _bunny(8117, 2, "left_near", tmp_path)
    _held(record)
    assert record.judged_succeeded, (record.judge_reason, record.summary)


def test_a_bunny_that_slipped_out_in_the_weighing_is_held_harder_and_its_lift_says_when_it_goes(
        tmp_path: Path) -> None:
    """Held harder, the bunny is lifted, its watched pinch easing 1.6 %/s at 16 N, and slides off
    the pads' corners 11.4 s into the hold: main said success at 6 s and the judge's 2 s passed,
    5.4 s before it went ("A watched pinch says it holds on a steady slope")."""
    record = _bunny(50255, 1, "right_far", tmp_path)
    forces = [float(f) for f in re.findall(r"tactile_f\d ([\d.]+) N", _held(record))]
    assert min(forces) > 7.5, forces  # twice the 5 N asked, within force adaptation's band
    assert not record.task_succeeded and "grasp_lost" in record.summary, (record.judge_reason, record.summary)
