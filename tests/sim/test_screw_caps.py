"""Bottles and jars with screw caps, in both engines alike: a cap turned by a torque above
the thread's friction rises by the pitch per turn and comes free after the object's turns;
below that torque it stays; a free cap is lifted off by a pull, a threaded one is not; the
judge's truth (`SimRobot.caps`) says how far it turned, whether it is free and where it rests."""

from __future__ import annotations

import dataclasses
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from mcap.reader import make_reader

from atd.campaign.spec import WorldDraw
from atd.sim import load_description
from atd.sim.library import get, library
from atd.sim.scene import Scene
from atd.sim.simrobot import SimRobot
from atd.sim.thread import CapState, Thread, resting_place
from atd.sim.world import load_world
from factories.baxter.description import GRIPPER
from primitives.robot import HandMode
from tests.conftest import EXAMPLES

SCREW_CAPPED = [name for name, o in library().items() if o.thread is not None]
GRAVITY = 9.81


def _in_fixture(name: str, xy: tuple[float, float] = (0.15, 0.2)) -> Scene:
    """The library object, held upright in a fixture on the table at `xy`."""
    found = get(name).in_fixture()
    pose = np.eye(4)
    pose[:3, 3] = (*xy, found.size[-1] / 2)
    return Scene(found.body(name, pose))


def _cap(robot: SimRobot, name: str) -> CapState:
    return robot.caps()[name]


def _turn_until_free(robot: SimRobot, name: str, torque: float, limit: float = 6.0) -> list[tuple[float, float]]:
    """Turn the cap with `torque` until the thread lets it go: (turns, rise in m) each tick."""
    robot.hold_still(0.1)  # the closed cap settles on its thread
    closed = _cap(robot, name).pose[2, 3]
    robot.push_cap(name, torque)
    seen = []
    for _ in range(round(limit / robot.info.control_period)):
        robot.step()
        cap = _cap(robot, name)
        seen.append((cap.turns, cap.pose[2, 3] - closed))
        if cap.free:
            return seen
    raise AssertionError(f"the cap of {name} was not free after {limit} s of {torque} N m: {seen[-1]}")


def test_eight_household_bottles_and_jars_of_different_shapes_caps_and_threads() -> None:
    threads = [get(name).thread for name in SCREW_CAPPED]
    assert len(SCREW_CAPPED) >= 8
    assert {get(name).shape.value for name in SCREW_CAPPED} == {"cylinder", "box"}
    for kind in ("pitch", "turns", "torque", "cap_radius", "cap_mass"):
        assert len({getattr(t, kind) for t in threads}) >= 3, kind
    assert len({get(name).mass for name in SCREW_CAPPED}) >= 6
    # Every cap fits a two-finger pinch of every hand: wider than Baxter's narrowest (26 mm),
    # narrower than the Melfa's widest (68 mm); every neck fits inside its cap.
    assert all(0.026 < 2 * t.cap_radius < 0.068 and t.neck_radius < t.cap_radius for t in threads)


@pytest.mark.parametrize("name", ["water_bottle", "jam_jar", "syrup_bottle"])
def test_turning_the_cap_raises_it_by_the_pitch_per_turn_until_it_comes_free(robot_of, melfa, engine, name) -> None:
    thread = get(name).thread
    robot = robot_of(melfa, engine, _in_fixture(name))
    seen = _turn_until_free(robot, name, 1.2 * thread.torque)
    turns, rise = np.array(seen).T
    assert turns[-1] == pytest.approx(thread.turns, abs=0.01)
    threaded = slice(0, len(seen) - 1)  # every tick before it came free: rise = pitch x turns
    np.testing.assert_allclose(rise[threaded], thread.pitch * turns[threaded], atol=2e-4)
    assert rise[-2] == pytest.approx(thread.travel, abs=5e-4)
    assert np.all(np.diff(turns[threaded]) >= -1e-3)  # it only ever turned open


def test_below_the_thread_torque_the_cap_does_not_turn(robot_of, melfa, engine) -> None:
    thread = get("coffee_jar").thread
    robot = robot_of(melfa, engine, _in_fixture("coffee_jar"))
    robot.push_cap("coffee_jar", 0.8 * thread.torque)
    robot.hold_still(1.0)
    cap = _cap(robot, "coffee_jar")
    assert abs(cap.turned) < 0.01 and not cap.free and cap.rests == "bottle"


def test_a_threaded_cap_holds_a_pull_and_a_free_one_is_lifted_off(robot_of, melfa, engine) -> None:
    thread = get("juice_bottle").thread
    robot = robot_of(melfa, engine, _in_fixture("juice_bottle"))
    closed = _cap(robot, "juice_bottle").pose[2, 3]
    robot.push_cap("juice_bottle", force=(0.0, 0.0, 5.0))  # a pull of 5 N on the closed cap: the thread gives a little
    robot.hold_still(0.3)
    assert _cap(robot, "juice_bottle").pose[2, 3] - closed < 5e-4 and not _cap(robot, "juice_bottle").free
    robot.push_cap("juice_bottle", force=(0.0, 0.0, 0.0))
    _turn_until_free(robot, "juice_bottle", 1.5 * thread.torque)
    robot.hold_still(0.5)
    cap = _cap(robot, "juice_bottle")
    assert cap.free and cap.rests == "bottle"  # let go, it sits on the neck
    robot.push_cap("juice_bottle", force=(0.0, 0.0, 2 * thread.cap_mass * GRAVITY))  # twice its weight, up
    robot.hold_still(0.2)
    cap = _cap(robot, "juice_bottle")
    assert cap.pose[2, 3] - closed > 0.05 and cap.rests == "elsewhere"  # in the air: neither held nor resting


def test_the_judge_says_a_free_cap_pressed_against_the_hand_is_held(robot_of, melfa, engine) -> None:
    thread = get("spice_jar").thread
    # Under the parked hand (its TCP at x 0.125, y 0, 0.15 m high), so a cap pulled up meets it.
    robot = robot_of(melfa, engine, _in_fixture("spice_jar", (0.125, 0.0)))
    _turn_until_free(robot, "spice_jar", 1.5 * thread.torque)
    robot.push_cap("spice_jar", force=(0.0, 0.0, 3 * thread.cap_mass * GRAVITY))
    robot.hold_still(0.5)
    cap = _cap(robot, "spice_jar")
    assert cap.rests == "held" and cap.free and cap.pose[2, 3] > 0.11


def test_the_judge_says_a_cap_thrown_off_beside_the_bottle_rests_on_the_table(robot_of, melfa, engine) -> None:
    thread = get("vitamin_jar").thread
    robot = robot_of(melfa, engine, _in_fixture("vitamin_jar"))
    _turn_until_free(robot, "vitamin_jar", 1.5 * thread.torque)
    weight = thread.cap_mass * GRAVITY
    robot.push_cap("vitamin_jar", force=(0.0, weight, 2 * weight))  # up and away, as fast as it falls
    robot.hold_still(0.15)
    robot.push_cap("vitamin_jar")
    robot.hold_still(1.5)
    cap = _cap(robot, "vitamin_jar")
    assert cap.rests == "table" and cap.free and cap.turns == pytest.approx(thread.turns, abs=0.01)
    assert cap.pose[1, 3] > 0.2 + 0.05  # beside the jar, not on it


def test_a_free_cap_is_held_where_the_robot_touches_it_else_on_the_rim_or_the_table() -> None:
    thread = Thread(0.0125, 0.012, 0.015, 0.017, 0.0025, 0.004, 1.0, 0.04)
    height = 0.2
    bottle = np.eye(4)
    bottle[2, 3] = height / 2
    on_rim = thread.closed_cap(bottle, height)
    assert resting_place(thread, height, bottle, on_rim, free=False, touches_robot=True) == "bottle"
    assert resting_place(thread, height, bottle, on_rim, free=True, touches_robot=False) == "bottle"
    assert resting_place(thread, height, bottle, on_rim, free=True, touches_robot=True) == "held"
    lying = np.array([[1.0, 0, 0, 0.1], [0, 0, -1, 0], [0, 1, 0, thread.cap_radius], [0, 0, 0, 1]])  # on its side
    assert resting_place(thread, height, bottle, lying, free=True, touches_robot=False) == "table"
    assert resting_place(thread, height, bottle, lying, free=True, touches_robot=True) == "held"
    assert CapState(math.pi, True, lying, "table").turns == pytest.approx(0.5)


def _world(folder: Path, text: str):
    path = folder / "world.toml"
    path.write_text(text)
    return load_world(path)


def test_a_world_file_stands_a_bottle_in_a_fixture_and_drops_jars_into_a_box(robot_of, melfa, engine, tmp_path) -> None:
    world, found = _world(tmp_path, """
[[object]]
library = "water_bottle"
position = [0.15, 0.2]
fixture = true

[[container]]
name = "box"
position = [0.3, -0.15]
size = [0.30, 0.25, 0.12]

[[drop]]
objects = ["jam_jar", "spice_jar"]
into = "box"
""")
    assert world is not None and found == []
    scene = world.scene(Scene(), seed=0)
    assert [b.thread.fixture for b in scene.objects] == [True, False, False]
    robot = robot_of(melfa, engine, scene)
    assert robot.settling.moving == () and robot.objects_inside("box") == ["jam_jar", "spice_jar"]
    caps = robot.caps()
    assert list(caps) == ["water_bottle", "jam_jar", "spice_jar"]
    assert all(not c.free and c.rests == "bottle" and abs(c.turned) < 0.01 for c in caps.values())
    # A campaign's world draws from the same library.
    assert WorldDraw(objects=2, into="box", **{"from": ["jam_jar", "water_bottle"]}).from_ == ("jam_jar", "water_bottle")


@pytest.mark.parametrize("line, message, hint", [
    ('library = "duck"\nfixture = true', "'duck' has no screw cap: only a bottle or jar with one stands in a fixture",
     "jam_jar"),
    ('library = "jam_jar"\nfixture = "yes"', "'fixture' must be true or false, not 'yes'", "fixture = true"),
    ('shape = "box"\nsize = [0.05, 0.05, 0.05]\nfixture = true', "only a bottle or jar with a screw cap stands", "jam_jar"),
])
def test_a_fixture_for_what_has_no_screw_cap_is_a_located_error(tmp_path, line, message, hint) -> None:
    world, found = _world(tmp_path, f"[[object]]\nposition = [0.1, 0.0]\n{line}\n")
    assert world is None and [d.code for d in found] == ["WLD012"]
    assert message in found[0].message and found[0].loc.line >= 3 and hint in found[0].hint


def test_a_copy_posed_from_the_scene_state_shows_the_cap_on_its_thread_and_off_it(robot_of, melfa, engine) -> None:
    """What a video's renderer does: a fresh copy of the scene, posed as the run's was."""
    thread = get("vitamin_jar").thread
    run, copy = (robot_of(melfa, engine, _in_fixture("vitamin_jar")) for _ in range(2))
    for free in (False, True):
        if free:
            _turn_until_free(run, "vitamin_jar", 1.5 * thread.torque)
            run.push_cap("vitamin_jar", force=(0.0, 0.0, 2 * thread.cap_mass * GRAVITY))
        else:
            run.push_cap("vitamin_jar", 1.5 * thread.torque)
        run.hold_still(0.1)
        copy.set_scene_state(run.scene_state())
        # MuJoCo reports poses from the start of the last physics step, the copy's from its end.
        np.testing.assert_allclose(copy.caps()["vitamin_jar"].pose[:3, 3], run.caps()["vitamin_jar"].pose[:3, 3], atol=3e-3)


def test_atd_run_says_where_each_cap_is_and_records_it(tmp_path) -> None:
    world, recording = tmp_path / "world.toml", tmp_path / "run.mcap"
    world.write_text('[[object]]\nlibrary = "jam_jar"\nposition = [0.15, 0.2]\nfixture = true\n')
    run = [sys.executable, "-m", "atd", "run", str(EXAMPLES / "simple_move.xml"), "--robot", "melfa", "--world", str(world), "-q"]
    text = subprocess.run([*run, "--record", str(recording)], capture_output=True, text=True, timeout=300)
    assert text.returncode == 0, text.stderr
    assert "the cap of 'jam_jar': turned 0.00 turns, on its thread, on its bottle" in text.stdout.splitlines()
    with recording.open("rb") as f:
        truth = [json.loads(m.data) for _, channel, m in make_reader(f).iter_messages() if channel.topic == "/truth"]
    assert list(truth[-1]["objects"]) == ["jam_jar", "jam_jar:cap"]
    assert truth[-1]["objects"]["jam_jar:cap"]["position"] == pytest.approx({"x": 0.15, "y": 0.2, "z": 0.099}, abs=1e-3)
    found = json.loads(subprocess.run([*run, "--format", "json"], capture_output=True, text=True, timeout=300).stdout)
    cap = found["caps"]["jam_jar"]
    assert abs(cap["turns"]) < 1e-3 and (cap["free"], cap["rests"]) == (False, "bottle")
    assert cap["position"] == pytest.approx([0.15, 0.2, 0.105 - 0.006], abs=1e-3)  # on top of the jar


def test_a_bottle_placed_elsewhere_takes_its_cap_along(robot_of, melfa, engine) -> None:
    found = get("juice_bottle")
    pose = np.eye(4)
    pose[:3, 3] = (0.15, 0.2, found.size[-1] / 2)
    robot = robot_of(melfa, engine, Scene(found.body("juice_bottle", pose)))
    pose[:3, 3] = (0.2, -0.25, found.size[-1] / 2)
    robot.place_object(pose)
    robot.hold_still(0.3)
    cap = robot.caps()["juice_bottle"]
    assert cap.rests == "bottle" and not cap.free
    np.testing.assert_allclose(cap.pose[:3, 3], found.thread.closed_cap(pose, found.size[-1])[:3, 3], atol=1e-3)


def test_a_pinch_and_a_wrist_turn_unscrew_the_cap(robot_of, melfa, engine) -> None:
    """The fingers' contacts drive the thread: the Melfa pinches the cap with 10 N per pad
    and turns its wrist counter-clockwise seen from above (negative about its downward tool axis)."""
    thread = get("water_bottle").thread
    height = 0.144  # the cap, 17 mm tall, within the pads (24 mm either side of the TCP, 0.15 m high), the neck below them
    pose = np.eye(4)
    pose[:3, 3] = (0.125, 0.0, height / 2)
    bottle = dataclasses.replace(get("water_bottle").in_fixture().body("bottle", pose), size=(0.032, height))
    robot = robot_of(melfa, engine, Scene(bottle))
    hand = robot.info.hand
    robot.command_hand(hand.closing * 10.0, [HandMode.FORCE] * len(hand.dofs))
    robot.hold_still(1.0)
    assert (robot.read().pad_force > 5.0).all()  # more than the thesis's FINGER_GRASPING_FORCE
    turn = np.zeros(len(robot.info.arm_joints))
    turn[-1] = -0.5  # rad/s
    robot.command_arm_velocity(turn)
    for _ in range(round(2.0 / robot.info.control_period)):
        robot.step()
    cap = robot.caps()["bottle"]
    # The wrist turned 1 rad; the cap as far, or a little less where the pads slip (MuJoCo: 0.75 rad).
    assert 0.6 < cap.turned < 1.05 and not cap.free
    rise = cap.pose[2, 3] - thread.closed_cap(pose, height)[2, 3]
    assert rise == pytest.approx(thread.pitch * cap.turned / (2 * math.pi), abs=2e-4)


def test_the_baxters_rubber_jaws_squeezing_a_narrow_cap_stand_at_its_width(robot_of, engine) -> None:
    """A cap is as stiff against the Baxter's rubber-tipped jaws as against any hand: pressed with
    10 N they stand at the 30 mm cap's width, short of their 26 mm closed stop (MuJoCo's explicit
    contact pairs for the rubber once sank them 7 mm a side into a cap, to the stop on every cap
    under 48 mm, and the unscrew read them as closed on nothing)."""
    baxter = load_description("baxter")
    tcp = robot_of(baxter, engine).read().tcp[:3, 3]
    found = get("water_bottle").in_fixture()

    def cap_height(height: float) -> float:  # the closed cap's centre, the bottle `height` tall
        pose = np.eye(4)
        pose[:3, 3] = (tcp[0], tcp[1], height / 2)
        return float(found.thread.closed_cap(pose, height)[2, 3])

    low, high = 0.1, 0.2  # the cap rises as the bottle grows: its centre between the pads' centres
    height = low + (tcp[2] - cap_height(low)) * (high - low) / (cap_height(high) - cap_height(low))
    pose = np.eye(4)
    pose[:3, 3] = (tcp[0], tcp[1], height / 2)
    bottle = dataclasses.replace(found.body("bottle", pose), size=(found.size[0], height))
    robot = robot_of(baxter, engine, Scene(bottle))
    robot.command_hand(robot.info.hand.closing * 10.0, [HandMode.FORCE])
    robot.hold_still(1.0)
    gap = GRIPPER.gap_closed + 2.0 * float(robot.read().hand_q[0])  # both jaws open by the reading
    assert gap == pytest.approx(2 * found.thread.cap_radius, abs=1.5e-3)
