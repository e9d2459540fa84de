"""The three-finger robust grasp when the approach is not the one the ATD asked for (issue
10): left higher, the arm comes down at the approach velocity before the first contact, so
the grasp still ends well inside the 20 s the example gives it (at the correction velocity,
5 mm/s, the Barrett timed out in MuJoCo); left tilted, a grasp from above turns the hand
level before it comes down (tilted, one fingertip met the table first and the closing
fingers pushed the cylinder away)."""

from __future__ import annotations

import pytest

from atd.campaign.perturbation import approach_taken
from atd.model import load_task
from atd.model.vocabulary import HandShape
from atd.runtime.session import Run
from factories.registry import create
from tests.primitives.conftest import EXAMPLES, lifted_but_at_most_one
from translator import translate

TASK = EXAMPLES / "grasp_and_lift.xml"
LIFTED = 0.04 + 0.05  # m: the cylinder's centre at least 5 cm above where it stood


def _lift_with_error(arm: str, engine: str, **error: float) -> tuple[Run, object]:
    task, _ = load_task(TASK)
    factory = create("tombatossals", arm=arm)
    estd = translate(task, factory).estd
    values = {"dx": 0.0, "dy": 0.0, "dz": 0.0, "roll": 0.0, "pitch": 0.0, "yaw": 0.0, **error}
    run = Run(approach_taken(estd, values), factory, engine=engine)
    outcome = run.execute()
    assert outcome.succeeded and run.object_position[2] > LIFTED, (outcome.summary, run.object_position)
    return run, outcome


@pytest.mark.parametrize("engine", ["mujoco", "pybullet"])
@pytest.mark.parametrize("arm", ["right", "left"])
def test_an_approach_ending_3_cm_too_high_still_grasps_and_lifts(arm: str, engine: str) -> None:
    _, outcome = _lift_with_error(arm, engine, dz=0.03)
    grasp = next(v for v in outcome.visits if v.path == "grasp_object")
    assert grasp.left - grasp.entered < 12.0, grasp.left - grasp.entered


@pytest.mark.parametrize("engine", ["mujoco", "pybullet"])
def test_a_tilted_approach_from_above_is_levelled_and_lifts(engine: str) -> None:
    """The Barrett left 10 degrees about x and -8 about y; in MuJoCo the SDH2 still loses
    such a cylinder (issue 10's note)."""
    run, _ = _lift_with_error("right", engine, roll=10.0, pitch=-8.0)
    hand_z = run.robot.read().tcp[:3, 2]
    assert hand_z[2] < -0.99, hand_z  # the hand's approach axis points down, within 8 degrees


def test_the_approach_looks_for_contact_only_once_the_levelled_hand_is_still() -> None:
    """Trials 0 and 2 of the preset's SDH2/MuJoCo/tape cell with the approach error: the
    jolt of turning the hand level, and its weight loading the wrist differently once
    turned, read as a contact, and the fingers closed in the air (both failed at 1df1356)."""
    from tests.primitives.conftest import preset_trials

    for record in preset_trials((0, 2), robot="tombatossals", arm="left", engine="mujoco", grasp="robust",
                                object="tape", perturbation="approach"):
        assert record.judged_succeeded and record.task_succeeded, (record.judge_reason, record.summary)


@pytest.mark.parametrize(("arm", "engine", "obj", "index"), [
    ("left", "mujoco", "stapler", 0),  # the SDH2
    ("left", "pybullet", "spray", 0),
    ("right", "pybullet", "cylinder", 1),  # the Barrett
])
def test_a_finger_that_lands_on_the_objects_top_moves_the_hand_over_the_object(
        arm: str, engine: str, obj: str, index: int) -> None:
    """Preset trials with the approach error where the first contact was one finger on the
    object's top: closing there pushed the object over or away (each failed at 22188e9, and
    the SDH2's stapler trial fails at 115c11b with the move switched off). Placed from the
    wrist's force and torque, the contact now moves the hand over it."""
    from tests.primitives.conftest import preset_trials

    [record] = preset_trials((index,), robot="tombatossals", arm=arm, engine=engine, grasp="robust", object=obj,
                             perturbation="approach")
    assert record.judged_succeeded and record.task_succeeded, (record.judge_reason, record.summary)


def test_after_moving_over_a_contact_the_approach_looks_for_contact_only_once_the_hand_is_still() -> None:
    """The SDH2 in MuJoCo, preset trials with the approach error: after the moves over a
    finger's contact on the object's top, stopping read 2.2-2.4 N on the wrist, the new
    approach took that for a contact, and the fingers closed 5-9 cm above the object (each
    failed at d315c53)."""
    lifted_but_at_most_one([("cylinder", 4), ("wood", 9), ("speaker", 7)], robot="tombatossals", arm="left",
                           engine="mujoco", grasp="robust", perturbation="approach")


@pytest.mark.parametrize(("engine", "obj", "index"), [("mujoco", "tape", 1), ("pybullet", "duck", 0)])
def test_a_hand_left_low_lifts_its_fingertips_off_the_table_in_time_to_search(engine: str, obj: str, index: int) -> None:
    """The Barrett left 4-5 cm too low: its closing fingertips swing down onto the table and
    wait while the arm backs off. At the thesis' 5 mm/s that wait took 4-5 s of every close,
    and the search across the pinch line ran out of the grasp's 20 s (both timed out at
    22188e9); the back-off now has its own velocity."""
    from tests.primitives.conftest import preset_trials

    [record] = preset_trials((index,), robot="tombatossals", arm="right", engine=engine, grasp="robust",
                             object=obj, perturbation="approach")
    assert record.judged_succeeded and record.task_succeeded, (record.judge_reason, record.summary)


@pytest.mark.parametrize("engine", ["mujoco", "pybullet"])
@pytest.mark.parametrize(("arm", "dx", "dy", "within"), [
    ("right", 0.0, -0.03, 12.0),  # the Barrett: the cylinder 3 cm across its pinch line
    ("left", -0.03, 0.0, 6.0),  # the SDH2
])
def test_fingers_that_close_past_the_object_without_touching_it_search_at_once(
        arm: str, engine: str, dx: float, dy: float, within: float) -> None:
    """Closing on nothing, the pads pass within half the object's least width (the task's
    4 cm cylinder) of each other: nothing can be between them, and the search moves on
    from there. Closing on to the fingers' limits first, the grasps took 12.3 and 18.9 s
    (Barrett, MuJoCo and PyBullet) and 8.0 and 7.3 s (SDH2); now 10.5, 8.9, 4.8 and 3.8 s."""
    _, outcome = _lift_with_error(arm, engine, dx=dx, dy=dy)
    grasp = next(v for v in outcome.visits if v.path == "grasp_object")
    assert grasp.left - grasp.entered < within, grasp.left - grasp.entered


@pytest.mark.parametrize("index", [4, 14])
def test_a_preshape_blocked_on_the_table_is_made_again_higher_up(index: int) -> None:
    """The Barrett in PyBullet with the preset's approach error: the preshape's descent met
    the table at 48 N, the spread could not turn its fingers to face each other (0.72 rad
    of pi/2), and the pinch closed on the table, not across the stapler (each failed at
    398f6d7). The hand rises 2 cm and makes its preshape in free air first."""
    from tests.primitives.conftest import preset_trials

    [record] = preset_trials((index,), robot="tombatossals", arm="right", engine="pybullet", grasp="robust",
                             object="stapler", perturbation="approach")
    assert record.judged_succeeded and record.task_succeeded, (record.judge_reason, record.summary)


def _approach_param(arm: str, name: str, shape: str = "pinch_grasp", config=None):
    """A parameter of the grasp state's arm controller (the robust approach), as translated."""
    task, _ = load_task(TASK)
    grasps = {"preshape_hand": f"{shape}_preshape", "grasp_object": shape, "lift_object": shape}
    states = [s.model_copy(update={"hand_shape": HandShape(grasps[s.name])}) if s.name in grasps else s
              for s in task.states]
    estd = translate(task.model_copy(update={"states": states}), create("tombatossals", arm=arm, config=config)).estd
    [state] = [s for s in estd.states if s.name == "grasp_object"]
    return state.arm.params[name]


def _follows_surface(arm: str, shape: str = "pinch_grasp", config=None) -> bool:
    """Whether the grasp state's sliding grasp follows the table down, as translated."""
    return _approach_param(arm, "follow_surface", shape, config)


def test_only_the_barretts_pinch_leaves_its_fingertips_to_rise_off_the_table(tmp_path) -> None:
    """The Barrett's pinching fingertips, kept on the table, slid under an object's bottom
    edge and lifted one side of it; its cylindrical grasp keeps following the table (D5's
    orientation correction squares a box in it), as does the SDH2's pinch. A config says
    otherwise where a user wants it."""
    assert not _follows_surface("right")
    assert _follows_surface("right", "cylindrical_grasp") and _follows_surface("left")
    config = tmp_path / "follow.toml"
    config.write_text("[tombatossals.controllers.robust_grasp_approach]\nfollow_surface = true\n")
    assert _follows_surface("right", config=config)


def test_the_sliding_grasp_backs_off_no_further_than_closing_fingertips_swing_down() -> None:
    """The SDH2 in PyBullet with the preset's approach error: a close whose fingers pushed
    the hand up (jammed on the object's edge) had the sliding grasp back off 4 to 5 cm over
    5 s, and every later close and search step was made above the object (each failed at
    deaccd7). The slide backs off no further than the closing fingertips swing down (the
    SDH2's pinch: 4 mm) and 5 mm: the Barrett's, whose fingertips swing 18 mm, further."""
    lifted_but_at_most_one([("speaker", 17), ("wood", 7)], robot="tombatossals", arm="left", engine="pybullet",
                           grasp="robust", perturbation="approach")


def test_how_far_a_sliding_grasp_may_back_off_comes_from_the_hands_geometry() -> None:
    """The pinch's fingertips swing down 4 mm (SDH2) and 18 mm (Barrett) on their way from
    the preshape to the grasp; each slide may back off that far and 5 mm more."""
    assert _approach_param("left", "max_back_off") == pytest.approx(0.0089, abs=5e-4)
    assert _approach_param("right", "max_back_off") == pytest.approx(0.0227, abs=5e-4)


@pytest.mark.parametrize(("engine", "obj", "index"), [
    ("mujoco", "stapler", 0), ("mujoco", "speaker", 10),
    ("pybullet", "stapler", 1), ("pybullet", "speaker", 5),
])
def test_an_object_the_closing_fingers_push_off_their_line_is_grasped_where_it_went(
        engine: str, obj: str, index: int) -> None:
    """The Barrett with the preset's approach error: its closing fingertips met the box's
    end on a slope and pushed it out across their line, 4.5 cm, until it cleared them; the
    search, which looks 2.3 cm either side of where the hand first closed, pushed it out
    again at every close and the grasp timed out (each failed at 79fa868). Where the pads
    last felt it, above the table, says which side it went: the next close is made there."""
    from tests.primitives.conftest import preset_trials

    [record] = preset_trials((index,), robot="tombatossals", arm="right", engine=engine, grasp="robust",
                             object=obj, perturbation="approach")
    assert record.judged_succeeded and record.task_succeeded, (record.judge_reason, record.summary)


def test_a_pinch_whose_weight_hangs_off_its_line_is_set_down_and_grasped_across_it() -> None:
    """The Barrett pinched the preset's mug by its rim (MuJoCo, the approach error, trial
    9), the cup's weight 2 cm off the pinch line: the lift said success and the cup turned
    out of the hand in the judge's hold (the false success of the preset at 25ba1d9). Now
    the grasp lifts what it holds 1.5 cm, feels on the wrist where the weight hangs, sets
    it down and grasps it again across its centre of mass; the lift holds it."""
    from tests.primitives.conftest import preset_trials

    [record] = preset_trials((9,), robot="tombatossals", arm="right", engine="mujoco", grasp="robust",
                             object="mug", perturbation="approach")
    assert record.judged_succeeded and record.task_succeeded, (record.judge_reason, record.summary)
    held = next(why for e in record.events for why in e["why"] if why.startswith("object held"))
    off = float(held.split("its weight ")[1].split(" cm")[0])
    assert off <= 1.5, held
