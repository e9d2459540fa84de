"""The robust parallel-jaw grasp corrects an approach that left the jaws off the object
(issue 10): the grasp-and-lift example on the Melfa and the Baxter with a scripted approach
error, and objects of the campaigns' library, in both engines."""

from __future__ import annotations

from dataclasses import replace

import pytest

from atd.campaign.objects import get
from atd.campaign.perturbation import approach_taken
from atd.model import load_task
from atd.runtime.session import Run, belief_scene
from factories.registry import create
from primitives.arm.jaw_grasp import Bracket
from tests.primitives.conftest import EXAMPLES, preset_trials
from translator import translate

TASK = EXAMPLES / "grasp_and_lift.xml"
ENGINES = ("mujoco", "pybullet")
RISEN = 0.05  # m: the object's centre at least this far above where it stood, as the judge asks


def _grasp_with_error(robot: str, engine: str, obj: str | None = None, **error: float) -> tuple[bool, float, str]:
    """Run the task (with the library's `obj` in it, or the example's cylinder) with the
    approach off by `error` (m, degrees); the outcome, how far the object's centre rose,
    and how the arm says the grasp went."""
    task, _ = load_task(TASK)
    if obj is not None:
        task = task.model_copy(update={"object": get(obj).object_info(0.10, 0.0)})
    factory = create(robot)
    estd = translate(task, factory).estd
    scene = belief_scene(estd)
    if obj is not None:
        scene = replace(scene, object=get(obj).realize(scene.object))
    values = {"dx": 0.0, "dy": 0.0, "dz": 0.0, "roll": 0.0, "pitch": 0.0, "yaw": 0.0, **error}
    run = Run(approach_taken(estd, values), factory, engine=engine, scene=scene)
    outcome = run.execute()
    grasp = [r for r in run.trace.records if r["type"] == "event" and r["transition"] == "grasp_object->lift_object"]
    reasons = [c.get("reason", "") for c in grasp[0]["conditions"] if c.get("kind") == "arm_done"] if grasp else []
    rise = float(run.object_position[2]) - float(task.object.pose.position[2])
    return outcome.succeeded, rise, " ".join(reasons)


@pytest.mark.parametrize("robot", ("melfa", "baxter"))
@pytest.mark.parametrize("engine", ENGINES)
def test_a_jaw_landing_on_the_objects_top_moves_the_hand_across(robot: str, engine: str) -> None:
    """4.5 cm to the side: one jaw comes down on the cylinder's top, beside its outer face."""
    succeeded, rise, how = _grasp_with_error(robot, engine, dy=0.045)
    assert succeeded and rise > RISEN, (rise, how)
    assert "after 1 moves across" in how or "after 2 moves across" in how, how


@pytest.mark.parametrize("engine", ENGINES)
def test_jaws_closing_on_nothing_search_along_their_width_and_find_the_object(engine: str) -> None:
    """4.5 cm along the jaws' width, towards the robot: they close beside the cylinder, then
    the search finds it. (4.5 cm away from the robot also passed in PyBullet; in MuJoCo its
    search points closed on nothing until the grasp's timeout, see issue 10.)"""
    succeeded, rise, how = _grasp_with_error("melfa", engine, dx=-0.045)
    assert succeeded and rise > RISEN, (rise, how)
    assert "0 search points" not in how, how


@pytest.mark.parametrize("engine", ENGINES)
def test_a_tilted_approach_is_corrected_on_contact_and_lifts(engine: str) -> None:
    succeeded, rise, how = _grasp_with_error("melfa", engine, roll=12.0, pitch=-12.0, yaw=10.0)
    assert succeeded and rise > RISEN, (rise, how)


@pytest.mark.parametrize("engine", ENGINES)
def test_an_off_centre_object_met_by_one_jaw_first_is_grasped_where_it_stands(engine: str) -> None:
    """1 cm to the side: one pad touches first and the arm follows it (Melfa's tactile re-centring)."""
    succeeded, rise, how = _grasp_with_error("melfa", engine, dy=0.01, dz=-0.02)
    assert succeeded and rise > RISEN, (rise, how)
    assert "after 0 moves across and 0 search points" in how, how


def test_moves_across_that_turn_back_go_half_as_far_and_bracket_the_object() -> None:
    """A jaw on the top at +34 mm, then the other jaw on it: the object lies between the two."""
    bracket = Bracket()
    assert bracket.move(0.034) == 0.034
    assert bracket.move(-0.034) == pytest.approx(-0.017)
    assert bracket.move(0.034) == pytest.approx(0.0085)
    assert bracket.move(-0.01) == pytest.approx(-0.00425)


def test_a_move_across_stays_within_every_contact_so_far_not_only_the_last() -> None:
    """The Melfa's speaker (docs/robust-grasp.md): a jaw on it at -4 cm, the other jaw past it,
    back 2 cm, then that jaw on it again at +3.8 cm: the object lies between -2 cm and the first
    contact's place, so the hand goes 1 cm, not back past where it started."""
    bracket = Bracket()
    assert bracket.move(-0.04) == -0.04
    assert bracket.move(0.04) == pytest.approx(0.02)
    assert bracket.move(0.038) == pytest.approx(0.01)
    assert bracket.at == pytest.approx(-0.01)


@pytest.mark.parametrize("engine", ENGINES)
def test_an_object_shorter_than_the_pads_is_grasped_with_the_fingertips_clear_of_the_table(engine: str) -> None:
    """The 45 mm steel weight: closing level with its centre put the Melfa's fingertips on the
    table, whose push on the pads read as a grip with the jaws still open."""
    succeeded, rise, how = _grasp_with_error("melfa", engine, "weight")
    assert succeeded and rise > RISEN, (rise, how)


@pytest.mark.parametrize("engine", ENGINES)
def test_baxter_holds_a_roll_of_tape_its_ir_beam_passes_through(engine: str) -> None:
    """The IR sensor reads the table through the roll's core: the gripper alone judges the grasp."""
    succeeded, rise, how = _grasp_with_error("baxter", engine, "tape")
    assert succeeded and rise > RISEN, (rise, how)




def test_a_pad_meeting_the_object_on_its_rim_re_centres_without_pushing_it_away() -> None:
    """The preset's tape roll in MuJoCo, trial 1 (tilted 7-12 degrees): one pad meets the
    roll off its middle, so the jaws pause while the arm moves along their width. The arm
    also went on moving towards the touching pad as if the jaws were closing, and pushed
    the roll across the table: lost before, lifted now. (Trial 2 was lifted this way too
    until the arm spared joints near their limits: its first descent now stops on the
    roll's top and the wrist-placed move across leads the search astray; it times out.)"""
    [record] = preset_trials((1,), robot="melfa", engine="mujoco", grasp="robust", object="tape",
                             perturbation="approach")
    assert record.task_succeeded and record.judged_succeeded, (record.summary, record.judge_reason)


@pytest.mark.parametrize(("obj", "index"), [("wood", 5)])
def test_the_melfas_forearm_roll_stays_off_its_limit_at_the_wrist_singularity(obj: str, index: int) -> None:
    """A preset trial in PyBullet whose hand, tilted by the approach error, worked near the
    wrist singularity (j5 near 0, with the Melfa mounted level with the table): j4 and j6
    counter-rotated until j4 sat on its limit, a hardware failure. Sparing a joint near its
    limit leaves the turn to j6 (and the lower mount keeps j5 off 0): it lifts."""
    [record] = preset_trials((index,), robot="melfa", engine="pybullet", grasp="robust", object=obj,
                             perturbation="approach")
    assert record.task_succeeded and record.judged_succeeded, (record.summary, record.judge_reason)


@pytest.mark.parametrize(("obj", "index", "held"), [("tape", 5, "along the jaws off a rim"),
                                                     ("duck", 0, "the squeeze at its limit")])
def test_a_tilted_grip_that_loads_one_pad_more_holds_once_the_squeeze_is_at_its_limit(obj: str, index: int,
                                                                                      held: str) -> None:
    """Preset trials in MuJoCo whose hand, tilted by the approach error, closed on the object
    with one pad pressing more than the other (tape trial 0: 17 and 13 N, 15 N asked):
    the squeeze raised the motor to its +50 % limit and waited there for the weaker pad
    until the grasp's timeout. A still grip with the squeeze at its limit and both pads
    pressing 70 % of the force is taken as the grasp, and the lift says whether it holds;
    unless the weaker pad feels the object at its edge, the rest on a finger's bare rim: then
    the arm first moves along the jaws (tape trial 5: gripped at 14.7 N after one such move)."""
    [record] = preset_trials((index,), robot="melfa", engine="mujoco", grasp="robust", object=obj,
                             perturbation="approach")
    assert record.task_succeeded and record.judged_succeeded, (record.summary, record.judge_reason)
    grasped = [why for e in record.events if e["transition"] == "grasp_object->lift_object" for why in e["why"]]
    assert any(held in why for why in grasped), grasped


@pytest.mark.parametrize(("obj", "index"), [("stapler", 9), ("weight", 5)])
def test_a_search_rises_and_moves_across_in_one_motion_so_it_ends_within_the_grasps_time(obj: str, index: int) -> None:
    """Preset trials in MuJoCo whose jaws closed on nothing and searched: each rise came to
    a stop at its top before the move across began, and the 20 s the task gives the grasp
    ran out before the point that found the object. Passing the top within 5 mm, the arm
    goes straight on across."""
    [record] = preset_trials((index,), robot="melfa", engine="mujoco", grasp="robust", object=obj,
                             perturbation="approach")
    assert record.task_succeeded and record.judged_succeeded, (record.summary, record.judge_reason)


def test_jaws_that_brush_the_object_with_a_pads_edge_look_beyond_that_edge_next() -> None:
    """The preset's speaker trial 2 in PyBullet: the approach error left the jaws over the
    speaker's end, and closing, a pad's edge brushed it and pushed it away along the jaws'
    width; the jaws closed on nothing. The planned search went the other way first and ran
    out of time. The pads felt where the object was: the next point is a step beyond that edge."""
    [record] = preset_trials((2,), robot="melfa", engine="pybullet", grasp="robust", object="speaker",
                             perturbation="approach")
    assert record.task_succeeded and record.judged_succeeded, (record.summary, record.judge_reason)
