"""Grasping in a box the robot knows (thesis 3.4.3): the walls are obstacles to the jaws.
A hand whose corrections followed its contacts into a wall wedged its jaws there; vision
turns the jaws across an object's narrow side, or along a wall that leaves no room across."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from atd.model.estd import Controller
from atd.model.task import ContainerInfo, Environment, Pose
from atd.sim import load_description
from primitives.arm.approach_phases import Phase
from primitives.arm.jaw_grasp import JawPhase
from primitives.base import Context, Status
from primitives.perception.container import approach_pose, clear_of_walls
from primitives.perception.generators import VisionSettings, clear_jaws, jaw_yaw, long_side, under_jaws
from primitives.registry import build_controller
from atd.sim.simrobot import robot_info
from primitives.robot import Readings
from tests.primitives.box_worlds import BELIEF, BOX, BOX_POSE, WALL
from tests.primitives.melfa_jaws import GRASP_HEIGHT, MELFA, closing_correction, still

MELFA_OPEN = (0.04, 0.05)  # the WRT-102 open: along the hand's x, and along y where its jaws close
LOW_X, LOW_Y = 0.07, 0.06  # the inside of the box spans x 0.07-0.29, y 0.06-0.24 (tests.primitives.box_worlds)
HIGH_Y = 0.24
RIM_Z = BELIEF.rim


def _tcp(x: float, y: float, yaw: float = 0.0) -> np.ndarray:
    return approach_pose(BELIEF, np.array([x, y, 0.05]), 0.0, 0.0, yaw)


def test_a_hand_near_a_wall_is_moved_in_by_its_reach_and_slides_along_it() -> None:
    moved = clear_of_walls([BELIEF], _tcp(0.20, HIGH_Y - 0.01), MELFA_OPEN)[:3, 3]
    np.testing.assert_allclose(moved[:2], (0.20, HIGH_Y - 0.05))  # jaws closing towards the wall: 5 cm in
    turned = clear_of_walls([BELIEF], _tcp(0.20, HIGH_Y - 0.01, np.pi / 2), MELFA_OPEN)[:3, 3]
    np.testing.assert_allclose(turned[:2], (0.20, HIGH_Y - 0.04))  # the hand's narrower side towards it
    corner = clear_of_walls([BELIEF], _tcp(LOW_X, LOW_Y), MELFA_OPEN)[:3, 3]
    np.testing.assert_allclose(corner[:2], (LOW_X + 0.04, LOW_Y + 0.05))
    middle = _tcp(0.18, 0.15)
    np.testing.assert_array_equal(clear_of_walls([BELIEF], middle, MELFA_OPEN), middle)
    on_the_table = _tcp(0.50, 0.15)
    np.testing.assert_array_equal(clear_of_walls([BELIEF], on_the_table, MELFA_OPEN), on_the_table)
    beyond = _tcp(0.20, HIGH_Y + 0.03)  # past the wall: from the table, the table's
    np.testing.assert_array_equal(clear_of_walls([BELIEF], beyond, MELFA_OPEN), beyond)
    from_inside = clear_of_walls([BELIEF], beyond, MELFA_OPEN, start=np.array([0.20, HIGH_Y - 0.06, 0.05]))
    np.testing.assert_allclose(from_inside[:2, 3], (0.20, HIGH_Y - 0.05))  # from inside the box: kept in it


def test_a_hand_reaching_further_one_way_comes_nearer_a_wall_with_its_shorter_side_towards_it() -> None:
    """The SDH2's pinch reaches 8.9 cm towards its thumb (hand -x) and 5.0 cm the other way: its
    footprint's middle lies 1.9 cm towards the thumb. With its fingers towards the wall the TCP
    comes to 5.0 cm of it, with the thumb to 8.9 cm; a hand alike either way (no offset) to its
    extent either way round."""
    extent, offset = (0.06925, 0.068), (-0.01925, 0.0)
    high_x = LOW_X + BELIEF.inner[0]
    fingers = clear_of_walls([BELIEF], _tcp(high_x - 0.01, 0.15), extent, offset=offset)[:3, 3]
    np.testing.assert_allclose(fingers[:2], (high_x - 0.050, 0.15))
    thumb = clear_of_walls([BELIEF], _tcp(high_x - 0.01, 0.15, np.pi), extent, offset=offset)[:3, 3]
    np.testing.assert_allclose(thumb[:2], (high_x - 0.0885, 0.15))
    alike = clear_of_walls([BELIEF], _tcp(high_x - 0.01, 0.15, np.pi), extent)[:3, 3]
    np.testing.assert_allclose(alike[:2], (high_x - 0.06925, 0.15))


def _still_at(tcp: np.ndarray) -> Readings:
    """The Melfa's readings, still, its TCP at `tcp`, touching nothing."""
    zeros = np.zeros(6)
    return Readings(time=0.0, arm_q=zeros, arm_dq=zeros, arm_effort=zeros, hand_q=np.zeros(2), hand_dq=np.zeros(2),
                    hand_effort=np.zeros(2), tcp=tcp, wrench=zeros, taxels={}, pad_force=np.zeros(2), range=None)


def _melfa_contexts() -> tuple[Context, Context]:
    """The Melfa's controller contexts: knowing the box, and knowing no container."""
    info = robot_info(load_description("melfa"))
    box = ContainerInfo(name="box", pose=Pose(matrix=tuple(BOX_POSE.reshape(-1))), size=BOX.size, wall=WALL)
    return (Context(info=info, params={}, environment=Environment(containers=(box,))),
            Context(info=info, params={}, environment=None))


def test_a_jaw_grasp_over_a_known_box_starts_its_descent_clear_of_the_wall() -> None:
    """The grasp's first move (and each move across or search after it) keeps the open jaws
    inside the walls; with no container known it descends where the approach left it."""
    start = _tcp(0.20, HIGH_Y - 0.015)
    readings = _still_at(start)
    ends = []
    for ctx in _melfa_contexts():
        grasp = build_controller(Controller(name="jaw_grasp_correction", params={"hand_extent": MELFA_OPEN}), "arm",
                                 ctx)
        grasp.start(readings)
        ends.append(grasp.route[-1])
        grasp._rise(readings, np.array([0.0, 0.05, 0.0]))  # a search point past the far wall
        ends.append(grasp.route[-1])
    np.testing.assert_allclose(ends[0][:2], (0.20, HIGH_Y - 0.05))
    np.testing.assert_allclose(ends[1][:2], (0.20, HIGH_Y - 0.05))  # kept inside the box it started in
    np.testing.assert_allclose(ends[2][:2], (0.20, HIGH_Y - 0.015))
    np.testing.assert_allclose(ends[3][:2], (0.20, HIGH_Y + 0.035))
    assert ends[0][2] == pytest.approx(start[2, 3] + 0.02)  # risen by its clearance, then across


def test_closing_jaws_that_follow_an_object_against_a_wall_stop_at_the_wall() -> None:
    """While the jaws close the arm follows the pads' contact (`arm_nudge`); an object pressed
    against a wall draws it on, and over a known box the hand goes no nearer the wall than its
    reach (it pressed into the wall at 190-270 N before); on the table it follows on."""
    readings = _still_at(_tcp(0.20, HIGH_Y - 0.06))
    goals = []
    for ctx in _melfa_contexts():
        grasp = build_controller(Controller(name="jaw_grasp_correction", params={"hand_extent": MELFA_OPEN}), "arm",
                                 ctx)
        grasp.start(readings)
        grasp._close_here(readings, 0.0)
        ctx.blackboard.arm_nudge = np.array([0.0, 0.01, 0.0])  # 1 cm/s towards the wall
        for _ in range(400):  # 2 s
            grasp.update(readings, 0.005)
        goals.append(grasp.goal)
    assert goals[0][1] == pytest.approx(HIGH_Y - 0.05)  # the open jaws' reach from the wall
    assert goals[1][1] == pytest.approx(HIGH_Y - 0.04)  # 2 cm on


def _top(centre: tuple[float, float], length: float, width: float, yaw: float) -> np.ndarray:
    """Points of a flat rectangular top at the rim's height, turned by `yaw` about the vertical."""
    u, v = np.meshgrid(np.linspace(-length / 2, length / 2, 17), np.linspace(-width / 2, width / 2, 9))
    c, s = np.cos(yaw), np.sin(yaw)
    xy = np.column_stack([c * u.ravel() - s * v.ravel(), s * u.ravel() + c * v.ravel()]) + centre
    return np.column_stack([xy, np.full(len(xy), RIM_Z)])


def test_vision_turns_the_jaws_across_a_long_objects_narrow_side() -> None:
    for yaw in (0.0, 0.5, -1.2, np.pi / 2 - 0.1):
        top = _top((0.18, 0.15), 0.08, 0.04, yaw)
        assert long_side(top, BELIEF) == pytest.approx((yaw + np.pi / 2) % np.pi - np.pi / 2, abs=1e-6)
        turned = jaw_yaw(top, BELIEF, MELFA_OPEN)
        closing = approach_pose(BELIEF, np.array([0.18, 0.15, RIM_Z]), 0.0, 0.0, turned)[:3, 1]
        assert abs(closing[:2] @ (np.cos(yaw), np.sin(yaw))) < 1e-6  # jaws close across its length
    assert long_side(_top((0.18, 0.15), 0.05, 0.05, 0.3), BELIEF) == 0.0  # a square top: no long side


def test_vision_closes_the_jaws_along_a_wall_that_leaves_no_room_across() -> None:
    """A 5 cm cube 1 cm from the far wall: jaws closing towards the wall would be pushed 2.5 cm
    off its middle, so they close along the wall, whichever way the cube is turned."""
    for yaw in (0.0, 0.2, np.pi / 2):
        top = _top((0.18, HIGH_Y - 0.035), 0.05, 0.05, yaw)
        closing = approach_pose(BELIEF, np.array([0.18, 0.2, RIM_Z]), 0.0, 0.0, jaw_yaw(top, BELIEF, MELFA_OPEN))
        assert abs(closing[1, 1]) < 0.2, yaw  # the closing axis (hand y) runs along the wall (world x)


# The SDH2's pinch preshape as its factory gives it to vision (`atd translate` of
# examples/empty_the_box_vision.xml, left arm): fingertips 4.8-6.8 cm out along the closing line,
# its thumb 9.0-10.7 cm behind the pinch, its footprint's middle 3.8 cm towards the thumb.
SDH2_VISION = VisionSettings(floor_margin=0.01, wall_margin=0.01, above_rim=0.1, voxel=0.01, min_points=20,
                             grasp_extent=(0.08847, 0.05), jaw_band=(0.048062, 0.067562, 0.011),
                             footprint=(0.069235, 0.068116, -0.038235, 0.0), other_tips=(-0.10747, -0.08947, 0.011))


def _sdh2_lands_on(seen: np.ndarray, pose: np.ndarray) -> int:
    """Points of `seen` under the SDH2's fingertips or thumb at `pose`, kept inside the walls."""
    extent, offset = SDH2_VISION.walls
    return under_jaws(seen, clear_of_walls([BELIEF], pose, extent, offset=offset), SDH2_VISION.jaw_band,
                      SDH2_VISION.other_tips)


@pytest.mark.parametrize("under", ["fingertip", "thumb"])
def test_vision_turns_the_sdh2_s_pinch_until_neither_its_fingertips_nor_its_thumb_come_down_on_a_neighbour(
        under: str) -> None:
    """A block lies along the box's x; the pinch closes across its 4 cm. A second block beside
    it, under a fingertip (6 cm off along the closing line) or under the thumb (10 cm behind
    the pinch), stopped the SDH2's descent over it and the pinch closed on nothing (14 of 15
    such grasps at seed 58238, docs/empty-the-box.md). Vision turns the pinch until neither
    comes down on what the picture shows, its footprint kept inside the walls."""
    centre = np.array([0.18, 0.15, RIM_Z])
    top = _top((0.18, 0.15), 0.07, 0.04, 0.0)
    extent, offset = SDH2_VISION.walls
    first = approach_pose(BELIEF, centre, 0.0, 0.0, jaw_yaw(top, BELIEF, extent, None, offset))
    way = first[:2, 1] * 0.058 if under == "fingertip" else first[:2, 0] * -0.098
    neighbour = _top(tuple(centre[:2] + way), 0.02, 0.02, 0.0)
    seen = np.concatenate([top, neighbour])
    assert _sdh2_lands_on(neighbour, first) > 0
    cleared = clear_jaws(first, centre, seen, BELIEF, SDH2_VISION)
    assert _sdh2_lands_on(neighbour, cleared) == 0


@pytest.mark.parametrize("arm", ["right", "left"])
def test_a_multi_finger_grasp_over_a_known_box_first_moves_its_hand_clear_of_the_wall(arm: str) -> None:
    """The robust grasp (Barrett, SDH2) keeps its preshaped hand inside the walls as the jaw
    grasp does: over the box and too near a wall it moves in first; on the table it starts its
    approach where the move left it."""
    description = load_description("tombatossals", arm)
    info = robot_info(description)
    extent = (0.045, 0.06)  # a hand narrower than the box, its x along the box's x
    box = ContainerInfo(name="box", pose=Pose(matrix=tuple(BOX_POSE.reshape(-1))), size=BOX.size, wall=WALL)
    start = _tcp(0.20, HIGH_Y - 0.015)
    zeros = np.zeros(len(info.arm_joints))
    hand = np.zeros(len(info.hand.dofs))
    readings = Readings(time=0.0, arm_q=zeros, arm_dq=zeros, arm_effort=zeros, hand_q=hand, hand_dq=hand,
                        hand_effort=hand, tcp=start, wrench=np.zeros(6), taxels={},
                        pad_force=np.zeros(len(info.hand.pads)), range=None)
    phases = []
    for environment in (Environment(containers=(box,)), None):
        grasp = build_controller(Controller(name="robust_grasp_approach", params={"hand_extent": extent}), "arm",
                                 Context(info=info, params={}, environment=environment))
        grasp.start(readings)
        phases.append(grasp.phase)
        if environment is not None:
            np.testing.assert_allclose(grasp.route[-1], (0.20, HIGH_Y - 0.06, start[2, 3]))
    assert phases[0] is Phase.ACROSS and phases[1] is Phase.APPROACH


def test_a_jaw_grasp_told_the_top_vision_saw_clears_it_and_closes_halfway_down_to_the_floor() -> None:
    """The task knows no object; the approach's top (`object_top`) stands in for it: the first
    descent starts with the fingertips clear of that top, and with no contact the jaws close
    round the middle of what stands under it (a short object: with the fingertips just over
    the floor, as with no top told)."""
    box, _ = _melfa_contexts()
    made = []
    for top in (0.095, 0.045, None):
        params = {"hand_extent": MELFA_OPEN, "fingertip_reach": 0.0238, **({} if top is None else {"object_top": top})}
        grasp = build_controller(Controller(name="jaw_grasp_correction", params=params), "arm", box)
        start = _tcp(0.18, 0.15)
        start[2, 3] = 0.10
        grasp.start(_still_at(start))
        rise = grasp.route[0][2]
        grasp._start_descent(_still_at(start))
        made.append((rise, grasp._grasp_height()))
    over_the_floor = 0.01 + 0.0238 + 0.005  # the floor, the fingertips' reach under the TCP, their clearance
    assert made[0] == (pytest.approx(0.095 + 0.04), pytest.approx((0.095 + 0.01) / 2))  # a standing can: its middle
    assert made[1] == (pytest.approx(0.12), pytest.approx(over_the_floor))  # 2 cm up; a 3.5 cm object: low
    assert made[2] == (pytest.approx(0.12), pytest.approx(over_the_floor))


def test_a_jaw_grasp_told_the_top_vision_saw_does_not_close_with_the_fingertips_at_it() -> None:
    """A jaw meeting something before the fingertips are past the seen top: the jaws would
    close over it; the hand goes on to where the contact placed the object instead. With the
    fingertips 1.2 cm under it (a wood block lifted so), and with no top told, it closes."""
    box, _ = _melfa_contexts()
    phases = []
    for top, tcp_z in ((0.05, 0.0738), (0.05, 0.0618), (None, 0.0738)):
        params = {"hand_extent": MELFA_OPEN, "fingertip_reach": 0.0238, "max_shifts": 0,
                  **({} if top is None else {"object_top": top})}
        grasp = build_controller(Controller(name="jaw_grasp_correction", params=params), "arm", box)
        at = _tcp(0.18, 0.15)
        at[2, 3] = tcp_z
        grasp.start(_still_at(at))
        grasp._start_descent(_still_at(at))
        force = np.array([0.0, 0.0, -5.0])  # pushed up, in the hand's frame (its z points down)
        lever = np.array([0.0, 0.03, grasp.wrist_to_tcp])  # under one jaw, 3 cm across
        grasp._met(_still_at(at), np.concatenate([force, np.cross(lever, force)]))
        phases.append(grasp.phase)
    assert phases == [JawPhase.MOVE, JawPhase.CLOSE, JawPhase.CLOSE]


def test_a_jaw_grasp_pressed_hundreds_of_newtons_backs_off_rises_and_fails_rather_than_close_there() -> None:
    """Blind exploration, the preset's seed, trial 0: a grasp's move pressed the hand into a wall
    at 440-500 N and the jaws closed there; the lift, the rise and the move aside all met what
    held it, and the box ended `stuck`. Pressed WEDGED beyond the empty hand's load the jaws are
    not told to close: the hand moves the way the press pushes it, rises, and the grasp fails,
    saying why (the round then opens and rises: `missed`)."""
    ctx, arm = closing_correction()
    period = MELFA.control_period
    pressed = still(GRASP_HEIGHT, (0.0, 300.0, 0.0, 0.0, 0.0, 0.0))  # a wall pushes the hand to -y
    arm.update(replace(pressed, time=0.01), period)
    assert ctx.blackboard.contact  # a knock: still closing
    arm.update(replace(pressed, time=0.2), period)  # pressed on
    assert not ctx.blackboard.contact and arm.status is Status.RUNNING
    eased, risen = arm.route
    np.testing.assert_allclose(eased, np.add(GRASP_HEIGHT, (0.0, -0.01, 0.0)), atol=1e-9)
    assert risen[2] == pytest.approx(GRASP_HEIGHT[2] + 0.02)
    for point in (eased, risen):
        arm.update(still(tuple(point)), period)
    assert arm.status is Status.ERROR and "pressed 300 N: wedged" in arm.reason


def test_a_move_along_the_jaws_stays_inside_the_walls_and_with_no_room_searches_on() -> None:
    """Jaws that reopen off a finger's rim move along their width towards the object; that move
    pressed the hand into the box's wall (the recording above). It keeps inside the walls like
    every other move, and where a wall leaves no room the jaws do not close there again."""
    box, _ = _melfa_contexts()
    ends = []
    for felt in (1.0, -1.0):  # the object beyond a pad's edge towards the +x wall, then away from it
        grasp = build_controller(Controller(name="jaw_grasp_correction", params={"hand_extent": MELFA_OPEN}), "arm",
                                 box)
        readings = _still_at(_tcp(0.29 - 0.04, 0.15))  # the open hand's reach from the +x wall
        grasp.start(readings)
        grasp._close_here(readings, 0.0)
        grasp._start_along(readings, felt)
        ends.append((grasp.phase, grasp.route[-1] if grasp.phase is JawPhase.MOVE else grasp.goal))
    (towards, searched), (away, along) = ends
    assert towards is JawPhase.MOVE and searched[0] <= 0.25 + 1e-9
    assert away is JawPhase.ALONG and along[0] == pytest.approx(0.25 - grasp.pad_half_width)
