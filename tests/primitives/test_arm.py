"""The shared arm controllers on the simulated Melfa: what a user would see the arm do."""

from __future__ import annotations

import math

import mujoco

import numpy as np
import pytest

from atd.model.estd import Controller as EstdController
from atd.model.vocabulary import EventType
from atd.sim.scene import DEFAULT_FRICTION, Body, Scene, box_scene
from primitives.arm.motion import turn_to_yaw
from primitives.base import Context, Status
from primitives.registry import build_controller
from primitives.values import Approach, Contact
from tests.primitives.conftest import (Stage, both_done, events, execute, last_reasons, leaf, machine, melfa,
                                      pushed_still, tcp, use)

FINGERTIP = 0.0238  # m from the Melfa's TCP down to its fingertips (PG70 pad half length)
ASIDE = box_scene(xy=(0.0, 0.22))  # the box out of the way


def test_guarded_move_stops_on_contact_with_the_table_and_the_next_move_rises_off_it() -> None:
    """The move that follows starts as the table's knock still rings in the wrist: it rises
    off the table, not stopped by the ring as an unexpected contact (its tare on a ringing
    reading did, as after the unscrew's put-down)."""
    robot = melfa(ASIDE)
    estd = machine(
        Stage(use("cartesian_move", target=(0.2, -0.1, 0.1)), use("hold_position"), both_done()),
        Stage(use("cartesian_move", target=(0.2, -0.1, -0.05), straight_line=True), use("hold_position"), both_done()),
        Stage(use("cartesian_move", target=(0.2, -0.1, 0.05)), use("hold_position"), both_done()),
        failures={"s2": (EventType.ERROR, leaf("arm_error"))},
    )
    stopped: list = []
    outcome, executor = execute(estd, robot, lambda robot, state, time: state == "s1" and stopped.append(tcp(robot)))
    assert [e["event"] for e in events(executor)] == ["success"] * 3, last_reasons(executor)
    assert "stopped on contact" in _reasons_leaving(executor, "s1")[0]
    fingertip = stopped[-1][2] - FINGERTIP
    assert -0.004 < fingertip < 0.002, f"fingertips {fingertip * 1000:.1f} mm from the table top"
    assert abs(stopped[-1][0] - 0.2) < 0.003 and abs(stopped[-1][1] + 0.1) < 0.003  # it came straight down
    assert abs(tcp(robot)[2] - 0.05) < 0.0035  # and rose off the table


def _recorder(path: list) -> callable:
    def hook(robot, state, time):
        path.append((state, time, robot.read().tcp.copy()))
    return hook


def test_free_move_reaches_the_target_top_down() -> None:
    robot = melfa(ASIDE)
    estd = machine(Stage(use("cartesian_move", target=(0.05, 0.12, 0.22)), use("hold_position"), both_done()))
    outcome, _ = execute(estd, robot)
    assert outcome.succeeded, outcome.summary
    pose = robot.read().tcp
    assert np.linalg.norm(pose[:3, 3] - (0.05, 0.12, 0.22)) < 0.0035
    assert pose[:3, 2] @ (0, 0, -1) > math.cos(math.radians(2))  # hand z points down
    assert outcome.sim_time < 3.0


def test_waypoints_are_visited_in_order() -> None:
    robot = melfa(ASIDE)
    via = ((0.2, 0.1, 0.15), (0.2, -0.1, 0.15))
    estd = machine(Stage(use("cartesian_move", target=(0.05, -0.1, 0.1), waypoints=via), use("hold_position"),
                         both_done()))
    path: list = []
    outcome, _ = execute(estd, robot, _recorder(path))
    assert outcome.succeeded, outcome.summary
    positions = np.array([pose[:3, 3] for _, _, pose in path])
    visits = [int(np.argmin(np.linalg.norm(positions - p, axis=1))) for p in via]
    assert all(np.linalg.norm(positions[i] - p) < 0.012 for i, p in zip(visits, via))
    assert visits[0] < visits[1]


def test_guarded_move_keeps_to_the_straight_line() -> None:
    robot = melfa(ASIDE)
    start, goal = np.array((0.125, 0.0, 0.15)), np.array((0.05, 0.15, 0.08))
    estd = machine(Stage(use("cartesian_move", target=tuple(goal), straight_line=True), use("hold_position"),
                         both_done()))
    path: list = []
    outcome, _ = execute(estd, robot, _recorder(path))
    assert outcome.succeeded, outcome.summary
    u = (goal - start) / np.linalg.norm(goal - start)
    off = [np.linalg.norm((p[:3, 3] - start) - ((p[:3, 3] - start) @ u) * u) for _, _, p in path]
    assert max(off) < 0.003, f"strayed {max(off) * 1000:.1f} mm from the line"


def test_constrained_move_keeps_within_velocity_and_acceleration_limits() -> None:
    robot = melfa(ASIDE)
    limits = (0.04, 0.04, 0.04, 0.0, 0.0, 0.0)
    estd = machine(Stage(use("cartesian_move", target=(0.05, 0.12, 0.1), keep_orientation=True,
                             velocity_limits=limits, acceleration_limits=(0.2,) * 3 + (0.0,) * 3),
                         use("hold_position"), both_done()))
    path: list = []
    outcome, _ = execute(estd, robot, _recorder(path))
    assert outcome.succeeded, outcome.summary
    times = np.array([t for _, t, _ in path])
    positions = np.array([p[:3, 3] for _, _, p in path])
    velocity = np.diff(positions, axis=0) / np.diff(times)[:, None]
    assert np.abs(velocity).max() < 0.04 * 1.1
    tilt = max(math.degrees(math.acos(min(1.0, -p[2, 2]))) for _, _, p in path)
    assert tilt < 2.0, f"the hand tilted {tilt:.1f} deg"
    assert np.abs(velocity).max(axis=0)[0] > 0.035  # it did use the speed it was allowed


def _wall_scene() -> Scene:
    """A 10 cm high block standing between the hand and a target on the far side."""
    wall = np.eye(4)
    wall[:3, 3] = (0.125, -0.1, 0.05)
    return Scene(box_scene(xy=(0.0, 0.22)).object, (Body("obstacle0", "box", (0.12, 0.04, 0.1), wall, 1.0,
                                                         DEFAULT_FRICTION),))


def test_free_move_bends_around_a_known_obstacle() -> None:
    robot = melfa(_wall_scene())
    target = (0.125, -0.25, 0.1)
    blocked = machine(Stage(use("cartesian_move", target=target), use("hold_position"), both_done()),
                      failures={"s0": (EventType.ERROR, leaf("arm_error"))})
    outcome, executor = execute(blocked, robot)
    assert not outcome.succeeded
    assert any("unexpected contact" in r for r in last_reasons(executor)), outcome.summary

    robot = melfa(_wall_scene())
    around = machine(Stage(use("cartesian_move", target=target, obstacles=((0.125, -0.1, 0.05),),
                               obstacle_sizes=((0.12, 0.04, 0.1),)), use("hold_position"), both_done()))
    path: list = []
    outcome, _ = execute(around, robot, _recorder(path))
    assert outcome.succeeded, outcome.summary
    lowest_over_wall = min(p[2, 3] - FINGERTIP for _, _, p in path if abs(p[1, 3] + 0.1) < 0.03)
    assert lowest_over_wall > 0.1, "the fingers passed through the top of the block"


def _grasp_box() -> list[Stage]:
    """Down onto the box under the hand, close on it, lift it 5 cm."""
    return [
        Stage(use("cartesian_move", target=(0.125, 0.0, 0.03), straight_line=True), use("hand_shape", shape="open"),
              both_done()),
        Stage(use("hold"), use("close_until_force", grasp_force=15.0), both_done()),
        Stage(use("cartesian_move", target=(0.125, 0.0, 0.08), straight_line=True), use("squeeze", grasp_force=15.0),
              both_done()),
    ]


def test_place_descends_until_the_object_touches_the_surface() -> None:
    robot = melfa()
    target = (0.125, 0.1, 0.025)
    estd = machine(*_grasp_box(),
                   Stage(use("place", target=target, approach_height=0.02), use("squeeze", grasp_force=15.0),
                         both_done()),
                   Stage(use("release_retreat"), use("open_to"), both_done()))
    path: list = []
    outcome, executor = execute(estd, robot, _recorder(path))
    assert outcome.succeeded, outcome.summary
    place = next(v for v in outcome.visits if v.path == "s3")
    assert any(r.startswith("placed") for r in _reasons_leaving(executor, "s3"))
    box = robot.object_pose()[:3, 3]
    assert np.linalg.norm(box[:2] - target[:2]) < 0.005
    assert abs(box[2] - 0.025) < 0.002  # resting on the table
    # the last 2 cm are a slow descent at VELOCITY (5 mm/s): at least 2 s for 1 cm
    assert place.left - place.entered > 2.0


def test_a_place_onto_what_stands_higher_than_its_target_puts_the_object_down_on_it() -> None:
    """The target on the table, a 4 cm block standing there (what was put down before): the
    held box meets the block while it is brought over, and is put down on it, the wrist
    pressing no harder than a guarded move's contact (it pressed until the state's timeout)."""
    block = np.eye(4)
    block[:3, 3] = (0.125, 0.1, 0.02)
    robot = melfa(Scene(box_scene().object, (Body("obstacle0", "box", (0.06, 0.06, 0.04), block, 1.0,
                                                  DEFAULT_FRICTION),)))
    pressed: list[float] = []
    estd = machine(*_grasp_box(),
                   Stage(use("cartesian_move", target=(0.125, 0.1, 0.1)), use("squeeze", grasp_force=15.0),
                         both_done()),
                   Stage(use("place", target=(0.125, 0.1, 0.025)), use("squeeze", grasp_force=15.0), both_done()),
                   Stage(use("release_retreat"), use("open_to"), both_done()))
    outcome, executor = execute(estd, robot, lambda robot, state, time: state == "s4" and pressed.append(
        float(np.linalg.norm(robot.read().wrench[:3]))))
    assert outcome.succeeded, outcome.summary
    assert any(r.startswith("placed on something") for r in _reasons_leaving(executor, "s4"))
    box = robot.object_pose()[:3, 3]
    assert abs(box[2] - 0.065) < 0.004, f"the box rests at {box[2]:.3f} m, not on the block"
    assert max(pressed) - pressed[0] < 30.0, f"the wrist read {max(pressed) - pressed[0]:.0f} N over its start"


def _reasons_leaving(executor, state: str) -> list[str]:
    fired = [r for r in executor.trace.records if r["type"] == "event" and r["state"] == state]
    return [c.get("reason", "") for r in fired for c in r["conditions"]]


def test_release_retreat_backs_off_only_while_pushed() -> None:
    robot = melfa(ASIDE)
    hand = mujoco.mj_name2id(robot.model, mujoco.mjtObj.mjOBJ_BODY, "pg70_base")
    start = tcp(robot)

    def push_from_below(robot, state, time):
        # fingers pressing on a surface as they open: 20 N up on the hand for a second (from
        # 0.2 s: a step in the very first tick reads as the last state's knock still ringing)
        robot.data.xfrc_applied[hand, 2] = 20.0 if 0.2 <= time < 1.2 else 0.0

    estd = machine(Stage(use("release_retreat", velocity=0.01), use("hold_position"), leaf("timeout", seconds=2.0),
                         seconds=5.0))
    heights: list = []
    outcome, _ = execute(estd, robot, lambda r, s, t: (push_from_below(r, s, t), heights.append((t, tcp(r)[2]))))
    assert outcome.succeeded
    risen_while_pushed = max(z for t, z in heights if t < 1.2) - start[2]
    assert 0.007 < risen_while_pushed < 0.013  # about 1 s at 0.01 m/s
    after = [z for t, z in heights if t > 1.4]
    assert max(after) - min(after) < 0.001  # holds still once the push is gone


def test_slide_presses_within_the_force_band_while_moving_and_does_not_claim_the_table() -> None:
    """Eq. 3.6's force band holds while the fingertips are dragged along the bare table (the
    target's height is where they press, no object being known); there is nothing carried,
    no drag beyond the fingers' own friction, so the slide ends in an error, not success."""
    robot = melfa(ASIDE)
    start = (0.2, -0.1, FINGERTIP + 0.003)
    target = (0.2, -0.06, 0.0)
    estd = machine(
        Stage(use("cartesian_move", target=start), use("hand_shape", shape="closed"), both_done()),
        Stage(use("slide", target=target), use("hold_position"), both_done(), seconds=20.0),
        failures={"s1": (EventType.ERROR, leaf("arm_error"))},
    )
    pressing: list = []

    def record(robot, state, time):
        if state == "s1":
            r = robot.read()
            pressing.append((time, r.tcp[:3, 3].copy(), r.wrench.copy()))

    outcome, executor = execute(estd, robot, record)
    assert not outcome.succeeded, outcome.summary
    assert any(r.startswith("moved nothing") for r in last_reasons(executor)), last_reasons(executor)
    assert abs(tcp(robot)[1] - target[1]) < 0.006
    load = max(pressing[:300], key=lambda sample: sample[1][2])[2][2]  # where it tared: highest, in free air
    forces = np.array([load - w[2] for _, p, w in pressing if p[1] > start[1] + 0.005])  # hand z down: pressing lowers fz
    assert 5.0 < np.median(forces) < 9.0
    assert np.mean((forces > 3.0) & (forces < 11.0)) > 0.8


def _heading(rotation: np.ndarray) -> float:
    """The hand x's direction about the world vertical, deg."""
    return math.degrees(math.atan2(rotation[1, 0], rotation[0, 0]))


def test_a_move_to_an_approach_turns_the_jaws_to_its_yaw_a_contact_only_moves_there() -> None:
    robot = melfa(ASIDE)
    start = _heading(robot.read().tcp[:3, :3])
    turned = math.radians(start + 60.0)
    pose = np.eye(4)
    pose[:3, 0], pose[:3, 2] = (math.cos(turned), math.sin(turned), 0.0), (0.0, 0.0, -1.0)
    pose[:3, 1] = np.cross(pose[:3, 2], pose[:3, 0])
    pose[:3, 3] = (0.05, 0.12, 0.22)
    memory = {"approach": Approach(pose, np.array([0.05, 0.12, 0.05]), "vision", 1),
              "touched": Contact(np.array([0.1, 0.1, 0.2]), "wrist", 4.0, np.array([0.0, 0.0, -1.0]), 1.0)}
    estd = machine(Stage(use("cartesian_move"), use("hold_position"), both_done()),
                   Stage(use("cartesian_move"), use("hold_position"), both_done()))
    states = (estd.states[0].model_copy(update={"target_from": "approach"}),
              estd.states[1].model_copy(update={"target_from": "touched"}), *estd.states[2:])
    outcome, _ = execute(estd.model_copy(update={"states": states}), robot, memory=memory)
    assert outcome.succeeded, outcome.summary
    assert outcome.sim_time < 10.0
    hand = robot.read().tcp
    assert np.linalg.norm(hand[:3, 3] - (0.1, 0.1, 0.2)) < 0.0035
    assert hand[:3, 2] @ (0, 0, -1) > math.cos(math.radians(2))  # hand z points down
    turn = (_heading(hand[:3, :3]) - start + 180.0) % 360.0 - 180.0
    assert abs(turn - 60.0) < 3.0, turn  # within the move's 2 degrees; the contact's move kept the turn


def test_a_move_to_an_approach_for_a_point_off_the_tcp_puts_that_point_there_turned_with_the_hand() -> None:
    """A pinch that closes 19 mm off the TCP (the SDH2's) goes to vision's approach with its
    pinch, not its TCP, over the object, whichever way the approach turns the hand."""
    robot = melfa(ASIDE)
    turned = math.radians(_heading(robot.read().tcp[:3, :3]) + 60.0)
    pose = np.eye(4)
    pose[:3, 0], pose[:3, 2] = (math.cos(turned), math.sin(turned), 0.0), (0.0, 0.0, -1.0)
    pose[:3, 1] = np.cross(pose[:3, 2], pose[:3, 0])
    pose[:3, 3] = (0.05, 0.12, 0.22)
    estd = machine(Stage(use("cartesian_move", hand_point=(0.019, 0.0, 0.0)), use("hold_position"), both_done()))
    states = (estd.states[0].model_copy(update={"target_from": "approach"}), *estd.states[1:])
    memory = {"approach": Approach(pose, np.array([0.05, 0.12, 0.05]), "vision", 1)}
    outcome, _ = execute(estd.model_copy(update={"states": states}), robot, memory=memory)
    assert outcome.succeeded, outcome.summary
    hand = robot.read().tcp
    pinch = hand[:3, 3] + hand[:3, :3] @ (0.019, 0.0, 0.0)
    assert np.linalg.norm(pinch - (0.05, 0.12, 0.22)) < 0.0035
    assert np.linalg.norm(hand[:3, 3] - (0.05, 0.12, 0.22)) > 0.015  # the TCP stands off, along the turned hand x


def test_a_yaw_a_half_turn_away_turns_the_jaws_the_shorter_way_unless_that_winds_the_wrist_up() -> None:
    """Parallel jaws grip alike turned a half turn: asked for 120 degrees from where it points,
    the hand turns 60 the other way, so the wrist turns at most a quarter turn; but not past
    135 degrees from where the first turn started, or turn after turn winds the wrist to its limit."""
    level = np.array([[-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]])  # hand x along -x: 180 degrees
    start = math.pi
    assert _heading(turn_to_yaw(level, math.radians(300.0), start) @ level) == pytest.approx(120.0)
    assert _heading(turn_to_yaw(level, math.radians(240.0), start) @ level) == pytest.approx(-120.0)
    wound = turn_to_yaw(level, math.radians(60.0), start) @ level  # 120 degrees on from the start
    assert _heading(wound) == pytest.approx(-120.0)
    assert abs(_heading(turn_to_yaw(wound, 0.0, start) @ wound)) == pytest.approx(180.0)  # 60 on: 180 off


def test_a_yaw_that_would_take_the_wrist_roll_onto_its_stop_is_reached_the_other_way() -> None:
    """A perceived yaw 50 degrees on: the shorter turn would take a Baxter-like wrist roll
    (-3.06..3.06 rad, at -2.2 and turning -1 per turn of the hand) 0.9 rad further down, past
    its stop; the jaws grip alike turned a half turn, so the hand turns 130 degrees the other way
    and the roll ends far from both stops. The same yaw 50 degrees the other way needs no such turn."""
    level = np.array([[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]])  # hand x along +x, pointing down

    def room(turn: float) -> float:
        q = -2.2 - turn
        return min(q + 3.059, 3.059 - q)
    assert _heading(turn_to_yaw(level, math.radians(50.0), 0.0, room=room) @ level) == pytest.approx(-130.0)
    assert _heading(turn_to_yaw(level, math.radians(-50.0), 0.0, room=room) @ level) == pytest.approx(-50.0)
    assert _heading(turn_to_yaw(level, math.radians(50.0), 0.0) @ level) == pytest.approx(50.0)  # no roll told


def test_a_yaw_whose_half_turn_matters_is_kept_unless_the_wrist_roll_would_end_on_its_stop() -> None:
    """An approach that says its half turn matters (the SDH2's thumb towards a box's middle)
    is turned to: asked for 50 degrees, not the -130 a parallel jaw might take. Where that would
    take the wrist roll (at -3.5 of -4.45..4.45 rad, turning +1 per turn of the hand) onto its
    stop, the opposite way after all: a thumb towards a wall is the lesser harm (a PA10 stopped
    there, and its arm with it)."""
    level = np.array([[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]])  # hand x along +x, pointing down

    def room(turn: float) -> float:
        q = -3.5 + turn
        return min(q + 4.451, 4.451 - q)
    assert _heading(turn_to_yaw(level, math.radians(50.0), 0.0, False, room) @ level) == pytest.approx(50.0)
    assert _heading(turn_to_yaw(level, math.radians(-50.0), 0.0, False, room) @ level) == pytest.approx(130.0)
    assert _heading(turn_to_yaw(level, math.radians(-50.0), 0.0, False) @ level) == pytest.approx(-50.0)  # no roll told


def test_a_free_move_off_a_press_is_not_stopped_as_it_eases_but_by_a_contact_after_it() -> None:
    """The Barrett's `aside` in the box (seed 30100, docs/empty-the-box.md) started with its
    fingers blocked on what they had let go, the wrist pressed 40 N beyond the resting hand,
    up and across the path; against the start's tare the press easing as the hand left read
    as "unexpected contact: 40.7 N" and the run ended `stuck`."""
    robot = melfa()
    ctx = Context(info=robot.info, params={}, environment=None)
    move = build_controller(EstdController(name="cartesian_move", params={"target": (0.3, 0.1, 0.3),
                                                                          "force_threshold": 40.0}), "arm", ctx)
    pushed = pushed_still(robot)
    dt = 0.005
    move.start(pushed(0.0, (5.0, -18.0, 36.0)))
    for tick, left in enumerate(np.linspace(1.0, 0.0, 21)):  # eased in 0.1 s, as the hand left it
        move.update(pushed(tick * dt, (5.0 * left, -18.0 * left, 36.0 * left)), dt)
        assert move.status is Status.RUNNING, left
    move.update(pushed(21 * dt, (-30.0, 0.0, -30.0)), dt)  # then it meets something on its way
    assert move.status is Status.ERROR and "unexpected contact" in move.reason
    robot.close()
