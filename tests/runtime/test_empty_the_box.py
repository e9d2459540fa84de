"""Issue 31, thesis 3.4.3: the box-emptying examples run end to end on the robot's own
sensors, with values passed from perceive to the pick-and-place round."""

from __future__ import annotations

import base64
import json
import subprocess
from pathlib import Path

import numpy as np
import pytest
from mcap.reader import make_reader

from atd.api import run, translate
from atd.model.estd import Controller, EstdState
from atd.model.vocabulary import StateType
from atd.review.load import load
from atd.runtime.session import Run
from atd.runtime.values import MissingValue, arm_for, bind_inputs, topped
from factories.registry import create
from primitives.values import Approach, Contact, NothingFound
from tests.conftest import EXAMPLES, REPO
from tests.runtime.test_run_cli import atd

TWO_OBJECTS = REPO / "tests" / "data" / "empty_the_box" / "two_objects.toml"
BOX_DATA = REPO / "tests" / "data" / "empty_the_box"


def test_vision_empties_a_box_of_two_objects_on_the_melfa_and_says_what_it_took_out(tmp_path):
    trace = tmp_path / "t.jsonl"
    result = atd("run", str(EXAMPLES / "empty_the_box_vision.xml"), "--robot", "melfa", "--world", str(TWO_OBJECTS),
                 "--trace", str(trace), "-q")
    assert result.returncode == 0, result.stdout + result.stderr
    assert "outcome: succeeded: reached 'box_empty'" in result.stdout
    assert "in 'box' at the end: nothing (0 of 2 objects)" in result.stdout
    assert "taken out of 'box': ball, tape (2 of the 2 it held)" in result.stdout
    assert "grasp attempts: 2 in " in result.stdout
    records = [json.loads(line) for line in trace.read_text().splitlines()]
    # Each round's outcome reached the parent, which branched on it by name.
    outcomes = [r["atd"] for r in records if r["type"] == "event" and r["event"] == "outcome"]
    assert outcomes == ["put_away->placed/outcome", "take_one_out->aside/outcome"] * 2  # down, then placed, both times
    # The round's first move went where perceive found the object: its input, read at run time.
    found = [r["conditions"][0]["point"] for r in records if r["type"] == "event" and r["event"] == "object_found"]
    assert len(found) == 2 and all(-0.05 < p[0] < 0.25 and -0.2 < p[1] < 0.04 for p in found)


def test_a_ball_in_a_corner_that_no_jaw_fits_beside_is_rolled_off_both_walls():
    """Vision's approach over the ball, then free_one.xml: pressed from above and dragged towards
    the box's middle, the ball (5 cm) ends clear of both walls by more than the open hand's
    half width (4 cm), where a grasp from above fits; it lay 0 and 8 mm from them."""
    result = run(BOX_DATA / "free_one_round.xml", robot="melfa", world=BOX_DATA / "ball_in_a_corner.toml")
    assert result.end_state == "done" and "free_it/drag" in result.path, result.summary
    x, y, _ = result.object_positions["ball"]
    inside_x, inside_y = 0.24, 0.035  # the box's +x and +y inner walls (examples/empty_the_box_vision.xml)
    assert inside_x - x > 0.065 and inside_y - y > 0.065


@pytest.mark.parametrize("arm", ["left", "right"])
def test_free_one_s_drag_takes_a_pointing_finger_low_enough_to_move_a_roll_of_tape_off_a_wall(arm):
    """A roll of tape lies 5 mm from the -y wall. The Tombatossals' closed hands point a finger
    (the SDH2 its thumb, the Barrett F3), and free_one.xml's drags, stated for the hand's
    lowest point, take that fingertip 1.6 cm over the floor, as a gripper's jaws: the roll
    ends 3 cm or more off the wall. Taken to where a gripper's grasp centre drags (the tip
    3.6-4 cm over the floor), neither moved it (docs/empty-the-box.md, "free_one's drags for
    the hand's lowest point")."""
    result = run(BOX_DATA / "free_one_round.xml", robot="tombatossals", arm=arm,
                 world=BOX_DATA / "tape_by_a_wall.toml")
    assert result.end_state == "done" and "free_it/drag" in result.path, result.summary
    lay = -0.161  # the roll's middle's y as it lay (tape_by_a_wall.toml)
    assert result.object_positions["tape"][1] - lay > 0.03


def test_a_grasp_over_half_of_a_standing_speakers_top_holds_it():
    """A second look at an object the first aimed at (as after a miss) aims at a half of its
    top: the jaws close across the split, the half's offset along the pads, and hold the 5 x 5
    cm speaker (closing along the split, a jaw came down on its top: docs/empty-the-box.md)."""
    result = run(BOX_DATA / "half_grasp.xml", robot="melfa", world=BOX_DATA / "speaker_standing.toml")
    assert result.end_state == "held", result.summary


def test_vision_keeps_the_jaws_off_a_block_lying_beside_the_one_it_aims_at_and_the_grasp_holds():
    """Two blocks lie 2.1 cm apart; jaws closing across the 4 cm of the one vision aims at would
    come down with the far jaw on the other's top (its fingertips reach 3.4-4.4 cm off the
    middle), and the grasp ended "a jaw met something with the fingertips at the seen top". The
    approach slides the jaws off what the picture shows under them, and the jaws hold the block
    (docs/empty-the-box.md, "Jaws kept off what the picture shows")."""
    result = run(BOX_DATA / "one_look_grasp.xml", robot="melfa", world=BOX_DATA / "two_blocks.toml", seed=1)
    assert result.end_state == "held", result.summary


def test_vision_turns_the_sdh2_s_thumb_away_from_the_wall_and_its_pinch_holds_a_speaker_beside_it():
    """A speaker stands 1 cm from a wall, its 5 x 5 cm top with no long side: the SDH2's pinch
    closes along the wall, its thumb (8.9 cm out, its fingers 5.0 cm the other way) turned
    towards the wall or away from it. Towards it, the walls kept the pinch 7 cm off the speaker
    and it closed on nothing; vision turns the thumb to the middle, the grasp keeps the hand's
    own footprint inside the walls, and the pinch holds the speaker (docs/empty-the-box.md,
    "The SDH2's thumb towards the room")."""
    result = run(BOX_DATA / "one_look_grasp.xml", robot="tombatossals", arm="left",
                 world=BOX_DATA / "speaker_at_a_wall.toml")
    assert result.end_state == "held", result.summary


def test_vision_keeps_the_sdh2_s_fingertips_off_a_block_beside_the_one_it_aims_at_and_its_pinch_holds_it():
    """Two blocks lie along the box's x, 2.5 cm apart across it. The SDH2's pinch closing across
    the 4 cm of the one vision aims at came down with a fingertip (4.8-6.8 cm out) on the
    other's top and closed on nothing ("nothing between the fingers after 5 corrections"), as
    in 11 of the 15 grasps that took nothing at seed 58238; turned only that far, its thumb (10
    cm behind the pinch) came down on it instead. Vision turns the pinch until neither lands on
    what the picture shows, and it holds the block (docs/empty-the-box.md, "The SDH2's
    fingertips and thumb kept off what the picture shows")."""
    result = run(BOX_DATA / "one_look_grasp.xml", robot="tombatossals", arm="left",
                 world=BOX_DATA / "blocks_a_fingertip_apart.toml", seed=0)
    assert result.end_state == "held", result.summary


def test_vision_turns_the_barrett_s_pinch_across_a_block_lying_along_the_box_and_its_boxed_pinch_holds_it():
    """A wood block lies along the box's x, 4 cm off its middle. The Barrett's pinch closes
    along its hand's x: turned as vision turns jaws, it closed along the block's 7 cm with its
    pads 25 cm apart, and its preshape (28.2 x 22.4 cm from above) fits no way round inside the
    28 x 23 cm box, so the walls held it in the middle. Vision turns its closing line across the
    block, the hand makes its boxed pinch (third finger curled under the palm, pads 12.8 cm
    apart), and the pinch holds the block (docs/empty-the-box.md, "The Barrett's pinch across
    what vision saw")."""
    result = run(BOX_DATA / "one_look_grasp.xml", robot="tombatossals", arm="right",
                 world=BOX_DATA / "wood_along_x.toml")
    assert result.end_state == "held", result.summary


def test_a_random_blind_round_on_an_empty_spot_rises_out_at_once_and_costs_under_19_s():
    """Random blind needs many rounds, most of them on a spot with nothing there, so a round's
    simulated time decides whether it empties the box in its budget: the jaws that closed on
    nothing go up without stopping to open, at a free move's speed (the round cost 19.3 s when
    they opened first, 1.6 s, and rose at an explore's 4 cm/s, 4.2 s, with its grasp closing at
    two points; 15.0 s since. The draw over the whole floor comes down on another spot, where
    the grasp closes at three points: 18.0 s; docs/empty-the-box.md)."""
    result = run(BOX_DATA / "random_round.xml", robot="melfa")
    assert result.end_state == "done", result.summary
    assert "take_one_out/open_empty" not in result.path and "take_one_out/rise" in result.path
    assert result.sim_time < 19.0


def test_a_round_after_a_miss_reaches_as_fast_as_the_arm_not_waiting_for_the_jaws_to_reopen():
    """Most random blind rounds begin with the jaws the last grasp shut on nothing. The reach
    opened them at the hand shape's half speed, 1.62 s for the Melfa's 34 mm, while its arm was
    there sooner; it opens them at full speed now, as the grasp reopens them. The same draw
    twice in the empty box: the second round misses as before, its reach 0.82 s (1.62 s on
    main; docs/empty-the-box.md)."""
    estd = translate(BOX_DATA / "two_rounds_on_one_draw.xml", "melfa")
    outcome = Run(estd, create("melfa")).execute()
    assert outcome.end_state == "done", outcome.summary
    reach = next(v for v in outcome.visits if v.path == "second_round/reach")
    assert reach.left_on == ["success"] and reach.left - reach.entered < 1.2
    assert "second_round/rise" in [v.path for v in outcome.visits]


def test_a_grasp_comes_down_into_a_known_box_from_over_its_rim_at_a_free_move_s_speed():
    """Every random blind round comes down from 5 cm over the rim, where nothing can be met:
    the grasp goes down to just over the rim at a free move's speed, without rising first, and
    closes on the empty floor 1.5 s sooner (6.4 s on the grasp's 4 cm/s after a 2 cm rise;
    4.9 s now; docs/empty-the-box.md)."""
    result = run(BOX_DATA / "descent_into_box.xml", robot="melfa")
    assert result.end_state == "closed_on_nothing", result.summary
    assert result.sim_time < 5.6


def test_a_blind_look_feels_the_spray_can_lying_by_a_wall_that_made_the_preset_say_empty():
    """The preset's seed, Melfa, trial 2: a spray can lying 2.6 cm off the -y wall and 4.4 cm
    off the +x wall, in the band the look's lanes keep the Melfa's 5 cm-wide hand out of; the
    lanes passed it by under a millimetre and the task said the box was empty with the can in
    it (docs/empty-the-box.md). Going round the walls with the fingers alone, the look feels it:
    on main it ended on nothing_found."""
    result = run(BOX_DATA / "blind_look.xml", robot="melfa", world=BOX_DATA / "spray_by_a_wall.toml")
    assert result.end_state == "found", result.summary


def test_a_look_that_starts_holding_a_block_puts_it_out_and_goes_on_to_empty_the_box():
    """A hand that reaches blind exploration's look still gripping something (the preset's seed,
    Baxter, trial 0: a duck caught between the paddles as free_one.xml pressed on it, lifted as it
    rose): the look's close stops on the grip and its sweep cannot start. On main the look's error
    edge ended the task "stuck"; the look now says object_in_hand, put_out.xml carries it out
    and puts it down beside the box, and the next look's sweep finds the box empty
    (docs/empty-the-box.md)."""
    result = run(BOX_DATA / "held_look.xml", robot="melfa", world=BOX_DATA / "one_block.toml")
    assert result.end_state == "emptied", result.summary
    assert "empty_it/put_out/put_away/put_down" in result.path and result.path.count("empty_it/look") == 2
    x, y, z = result.object_positions["wood"]
    assert y > 0.10 and z < 0.05  # on the table beside the box (its +y wall at y 0.045)


@pytest.mark.parametrize("arm", ["right", "left"])
def test_a_blind_look_feels_the_spray_can_by_a_wall_with_either_tombatossals_hand(arm):
    """The same can, on the Barrett (right) and the SDH2 (left): their wider parts kept the ring
    round the walls 4.3 and 5.4 cm over the floor, over the can's top at 3.8 cm, and on main
    both ended on nothing_found with the can in the box. The Barrett goes along the walls at
    the lanes' height with its narrower side towards them; the SDH2 sweeps with its fingers
    stretched, 5 cm wide, not with its fist and its thumb 11.5 cm out."""
    result = run(BOX_DATA / "blind_look.xml", robot="tombatossals", arm=arm, world=BOX_DATA / "spray_by_a_wall.toml")
    assert result.end_state == "found", result.summary


@pytest.mark.parametrize("arm", ["right", "left"])
def test_a_blind_look_in_the_empty_box_still_finds_nothing_with_either_tombatossals_hand(arm):
    """Going along the walls at the lanes' height, neither hand reads a wall as an object."""
    result = run(BOX_DATA / "blind_look.xml", robot="tombatossals", arm=arm)
    assert result.end_state == "empty", result.summary


def test_a_stretched_sdh2_s_blind_look_puts_its_pinch_where_a_fingertip_felt_a_standing_can_and_holds_it():
    """A spray can stands 4 cm off a wall; the SDH2's look, its fingers stretched, lands on the
    can's top with a fingertip, the can's middle 4.8 cm from its TCP. On main the approach was
    where the TCP landed, and the grasp knocked the can over and ended missed (the preset's seed
    39356: 10 of 13 grasps after a look closed on nothing). Feeling beside it with the tip's edge
    over where it landed, the look puts the pinch under the tip's half that felt the can, the
    thumb towards the room, and the pinch holds it (docs/empty-the-box.md)."""
    result = run(BOX_DATA / "blind_look_grasp.xml", robot="tombatossals", arm="left",
                 world=BOX_DATA / "spray_standing.toml")
    assert result.end_state == "held", result.summary


@pytest.fixture(scope="module")
def empty_box(tmp_path_factory) -> tuple[subprocess.CompletedProcess, Path]:
    """Vision on an empty box, traced and recorded: one picture, no grasp."""
    where = tmp_path_factory.mktemp("empty_box")
    result = atd("run", str(EXAMPLES / "empty_the_box_vision.xml"), "--robot", "melfa", "--trace",
                 str(where / "t.jsonl"), "--record", str(where / "run.mcap"), "-q")
    return result, where


def test_an_empty_box_ends_in_success_on_nothing_found_with_no_grasp(empty_box):
    result, where = empty_box
    assert result.returncode == 0 and "outcome: succeeded: reached 'box_empty'" in result.stdout
    entered = [r["state"] for r in json.loads("[" + ",".join((where / "t.jsonl").read_text().splitlines()) + "]")
               if r["type"] == "enter"]
    assert entered == ["aside", "look", "box_empty"] and "grasp attempts" not in result.stdout


def test_the_recording_of_a_vision_run_holds_the_picture_and_its_points_and_the_report_shows_it(empty_box):
    result, where = empty_box
    assert result.returncode == 0, result.stdout + result.stderr
    (picture,) = load(where / "run.mcap").pictures  # the one perceive state's
    seen = picture.depth[picture.depth > 0]
    assert picture.camera and picture.depth.ndim == 2 and seen.size > picture.depth.size / 2
    assert 0.3 < float(np.median(seen)) < 3.0  # metres: the table and the box, seen from the robot's camera
    with open(where / "run.mcap", "rb") as f:
        clouds = [json.loads(m.data) for _, c, m in make_reader(f).iter_messages(topics=["/camera/points"])]
    (cloud,) = clouds
    assert cloud["frame_id"] == "world" and len(base64.b64decode(cloud["data"])) == 12 * seen.size
    page = where / "run.html"
    report = atd("report", str(where / "run.mcap"), "-o", str(page))
    assert report.returncode == 0, report.stdout + report.stderr
    text = page.read_text()
    assert "<h2>Depth camera</h2>" in text and '<figure id="pictures"><svg' in text and "<image" in text


MOVE = Controller(name="cartesian_move", params={"max_speed": 0.15})
REACH = EstdState(name="reach", type=StateType.MOVE, atd="reach", arm=MOVE, target_from="approach")


def test_a_target_from_a_value_is_its_tcp_position_and_an_approach_s_yaw_read_as_the_state_starts():
    pose = np.eye(4)
    pose[:3, :3] = [[0.5, 0.866025, 0.0], [0.866025, -0.5, 0.0], [0.0, 0.0, -1.0]]  # top down, hand x at 60 deg
    pose[:3, 3] = (0.1, -0.05, 0.2)
    approach = Approach(pose, np.array([0.1, -0.05, 0.04]), "vision", 2)
    assert arm_for(REACH, {"approach": approach}).params == {"max_speed": 0.15, "target": (0.1, -0.05, 0.2),
                                                             "yaw": pytest.approx(60.0)}
    touched = Contact(np.array([0.2, 0.0, 0.06]), "wrist", 4.0, np.array([0.0, 0.0, -1.0]), 3.0)
    assert arm_for(REACH, {"approach": touched}).params == {"max_speed": 0.15, "target": (0.2, 0.0, 0.06)}
    below = REACH.model_copy(update={"target_offset": (0.0, 0.01, -0.02)})
    assert arm_for(below, {"approach": touched}).params == {"max_speed": 0.15, "target": (0.2, 0.01, 0.04)}
    put = EstdState(name="put", type=StateType.PLACE, atd="put", arm=Controller(name="place"), target_from="approach")
    assert arm_for(put, {"approach": approach}).params == {"target": (0.1, -0.05, 0.2)}  # a place does not turn
    with pytest.raises(MissingValue, match="state 'reach' takes its target from 'approach': it holds NothingFound"):
        arm_for(REACH, {"approach": NothingFound("vision", "empty")})


def test_a_grasp_takes_the_top_its_approach_saw_as_the_state_starts():
    """Vision says how high the top it aimed at is; random blind knows none, and the grasp
    then runs as the task wrote it."""
    grasp = EstdState(name="grasp", type=StateType.GRASP, atd="grasp", top_from="approach",
                      arm=Controller(name="jaw_grasp_correction", params={"max_shifts": 1}))
    seen = Approach(np.eye(4), np.array([0.1, -0.05, 0.052]), "vision", 3, 0.0523456789)
    assert topped(grasp.arm, grasp, {"approach": seen}).params == {"max_shifts": 1, "object_top": 0.052346}
    blind = Approach(np.eye(4), np.array([0.1, -0.05, 0.01]), "random_blind")
    assert topped(grasp.arm, grasp, {"approach": blind}) is grasp.arm
    with pytest.raises(MissingValue, match="state 'grasp' takes the object's top from 'approach': it holds nothing"):
        topped(grasp.arm, grasp, {})
    explore = Controller(name="explore", params={"direction": (0.0, 0.0, -1.0)})  # takes no top: left as it is
    assert topped(explore, grasp, {"approach": seen}) is explore


def test_a_sub_task_input_takes_the_parent_s_value_by_its_own_name():
    memory = {"found": "the approach"}
    bind_inputs(EstdState(name="take", type=StateType.TASK, atd="take", inputs={"approach": "found"}), memory)
    assert memory == {"found": "the approach", "approach": "the approach"}
