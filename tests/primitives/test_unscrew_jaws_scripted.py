"""The unscrew's arm on a parallel gripper (thesis 3.3.6 mapped on a gripper) on scripted
situations from Table 3.5's traced failures in PyBullet (docs/unscrew-campaign.md): the
robot's own hand model and its factory's parameters, driven by a scripted cap instead of
physics. The TCP moves as the arm commands unless a jaw's tip would enter the cap, the
wrist then reading PUSH against the move; the jaws stand as open as the script says. The
jam jar's 60 mm cap, believed so, its axis on the world's z axis."""

from __future__ import annotations

import numpy as np

from atd.model.frames import axis_rotation
from atd.model.task import State
from atd.model.vocabulary import StateType
from atd.sim import load_description
from atd.sim.simrobot import robot_info
from factories.registry import create
from primitives.arm.unscrew import UnscrewArm
from primitives.arm.unscrew_phases import Phase
from primitives.base import Context, Status
from primitives.blackboard import SHORT_OF_TARGET, CapGrip
from primitives.registry import build_controller
from primitives.robot import Readings

RADIUS = 0.03  # m: the cap's
TOP = 0.10  # m: the cap's top, world z
PUSH = 30.0  # N the wrist reads while the arm holds a jaw on the cap (the Baxter's read 20-44 N there)
ON_TOP = 170.0  # N the wrist reads while the arm presses an open jaw down on the cap's top (the Baxter's 155-200 N)
BAND = 0.009  # m under the cap's top where a jaw beside it stopped (Melfa, PyBullet: 9 mm, 3 mm short of its depth)
DOWN = np.diag([1.0, -1.0, -1.0])  # the hand points down; its y, the jaws' line, is the world's -y


class ScriptedJaws:
    """A TCP that goes where the arm commands, a gripper `gap` m open, a wrist reading `force` (world)."""

    def __init__(self, robot: str, arm: str | None, at: tuple[float, float, float], gap: float) -> None:
        factory = create(robot, arm)
        self.info = robot_info(load_description(robot, arm))
        mapping = factory.map_node(State(name="unscrew_cap", type=StateType.UNSCREW, object_size=2 * RADIUS), None)
        self.ctx = Context(info=self.info, params={})
        self.arm: UnscrewArm = build_controller(mapping.arm, "arm", self.ctx)
        self.reach = factory.robot.hand_reach("open")  # m: the open jaws' tips under the TCP
        self.tcp = np.eye(4)
        self.tcp[:3, :3], self.tcp[:3, 3] = DOWN, at
        self.time, self.force, self.gap = 0.0, np.zeros(3), gap
        hand = self.info.hand
        self.grid = np.linspace(hand.closed[0], hand.open[0], 200)
        self.gaps = np.array([np.linalg.norm(np.subtract(*hand.pad_surfaces(np.array([q]))[:2, :3, 3]))
                              for q in self.grid])

    def read(self) -> Readings:
        """What the robot's sensors say: its joints (the wrist with room to twist), the TCP, the wrist, the jaws."""
        order = np.argsort(self.gaps)
        hand_q = np.array([np.interp(self.gap, self.gaps[order], self.grid[order])])
        n = len(self.info.arm_joints)
        arm_q = (self.info.arm_lower + self.info.arm_upper) / 2.0
        wrench = np.concatenate([self.tcp[:3, :3].T @ self.force, np.zeros(3)])
        return Readings(time=self.time, arm_q=arm_q, arm_dq=np.zeros(n), arm_effort=np.zeros(n),
                        hand_q=hand_q, hand_dq=np.zeros(1), hand_effort=np.zeros(1), tcp=self.tcp.copy(),
                        wrench=wrench, taxels={}, pad_force=np.zeros(2), range=None)

    def tips(self, position: np.ndarray) -> np.ndarray:
        """The two jaws' tips (world) with the TCP at `position`."""
        return np.array([position + DOWN @ np.array([0.0, side * self.gap / 2.0, self.reach]) for side in (1.0, -1.0)])


def _in_cap(tip: np.ndarray, skirt: float) -> bool:
    """Inside the cap, whose lower part, from BAND under its top, stands `skirt` m wider."""
    r = float(np.hypot(*tip[:2]))
    return tip[2] < TOP and (r < RADIUS or (tip[2] < TOP - BAND and r < RADIUS + skirt))


def test_a_jaw_stopped_down_the_caps_side_rises_over_its_top_before_moving_across() -> None:
    """The Melfa's PyBullet trial 5 (docs/unscrew-campaign.md): the open jaws came down with
    one on the cap's top, searched across, went down beside the cap and stopped on it 11 mm
    lower, 3 mm short of its depth (here, on a band 1.5 mm wider there). Risen SEAT_RISE from there, the jaw still stood
    beside the cap, and the move across pushed it into the cap's side with 320-450 N until
    the unscrew's timeout. Now the rise goes over the top the first stop felt, and the move
    across watches the wrist: the jaws get round the cap and pinch, no jaw held on it."""
    reach = create("melfa").robot.hand_reach("open")
    world = ScriptedJaws("melfa", None, (0.0, -0.006, TOP + reach), gap=0.068)  # the -y jaw's tip on the top
    world.ctx.memory[SHORT_OF_TARGET] = np.array([0.0, 0.0, -0.012])  # the guarded descent stopped 12 mm short
    arm, dt = world.arm, world.info.control_period
    readings = world.read()
    arm.start(readings)
    pressed = 0.0  # s the arm has held a jaw against the cap's side
    while world.time < 30.0 and arm.phase is not Phase.PINCH and pressed < 1.0:
        v = arm.update(readings, dt).arm.twist[:3]
        moved = world.tcp[:3, 3] + v * dt
        blocked = any(_in_cap(tip, skirt=0.0015) for tip in world.tips(moved))
        world.force = -PUSH * v / max(float(np.linalg.norm(v)), 1e-9) if blocked else np.zeros(3)
        sideways = blocked and abs(v[2]) < 0.5 * float(np.linalg.norm(v[:2]))
        pressed = pressed + dt if sideways else 0.0
        if not blocked:
            world.tcp[:3, 3] = moved
        world.time += dt
        readings = world.read()
    assert arm.phase is Phase.PINCH, (arm.phase, pressed, world.tcp[:3, 3])
    assert arm.tally.seated >= 2  # off the top, then off the band down its side
    tips = world.tips(world.tcp[:3, 3])
    assert all(float(np.hypot(*tip[:2])) > RADIUS for tip in tips) and tips[0][2] < TOP - BAND, tips


def test_a_motor_grip_with_one_jaw_pressing_the_cap_from_outside_is_no_pinch_until_the_arm_yields() -> None:
    """The Baxter's PyBullet trial 9 (docs/unscrew-campaign.md): the jaws came down 3 mm off
    the cap's axis along their line, and closing, one met the cap's side with the other still
    6 mm short of it, the arm holding the hand there. Its motor, the Baxter's only grip
    force, read the grasp force all the same, and the unscrew twisted with one jaw: 40
    twists, the cap back where it was after each. Now jaws standing wider than the believed
    cap, the wrist pushed along their line, do not count as a pinch: the arm yields the way
    the wrist is pushed until both jaws close on the cap, and twists only then."""
    world = ScriptedJaws("baxter", "left", (0.0, 0.003, TOP), gap=0.0676)
    arm, dt = world.arm, world.info.control_period
    arm.start(world.read())
    world.ctx.blackboard.cap = CapGrip(pinched=True, holding=True)  # the motor presses the grasp force
    while world.time < 6.0 and arm.phase is Phase.PINCH:
        off = float(world.tcp[1, 3])  # the hand's centre from the cap's axis, along the jaws' line
        world.gap = 2.0 * (RADIUS + abs(off))  # the far jaw stops on the cap, the near one that far off it
        world.force = np.array([0.0, -np.sign(off) * PUSH, 0.0]) if abs(off) > 0.0005 else np.zeros(3)
        readings = world.read()
        world.tcp[:3, 3] += arm.update(readings, dt).arm.twist[:3] * dt
        world.time += dt
    assert arm.phase is Phase.TWIST and arm.tally.twists == 1, arm.phase
    assert abs(world.tcp[1, 3]) < 0.0006, world.tcp[:3, 3]  # both jaws on the cap


def test_a_return_whose_open_jaw_meets_the_caps_top_gets_off_it_and_round_to_the_start_pose() -> None:
    """The Baxter's PyBullet `hardware_failure` trials (left arm, Table 3.5, seed 90413,
    docs/unscrew-campaign.md): a pull drew the jaws 11 mm up the cap, the untwist back to
    the start pose swung the open left jaw over the cap's top, and the return, which watched
    no force, held it pressed there at 155-200 N for 20 s until the arm's fault fired. Here
    the twist stalls (the script does not turn the hand), the jaws end 18 mm up and 10 mm
    across, one tip over the cap's top, and the hand opens. Now the return gets off the top,
    across over the start pose and down round the cap, and pinches there."""
    world = ScriptedJaws("baxter", "left", (0.0, 0.0, TOP - 0.012 + create("baxter", "left").robot.hand_reach("open")),
                         gap=0.0676)
    arm, dt = world.arm, world.info.control_period
    start = world.tcp[:3, 3].copy()
    arm.start(world.read())
    world.ctx.blackboard.cap = CapGrip(pinched=True, holding=True)
    while world.time < 10.0 and arm.phase is not Phase.RELEASE:  # twists, stalls, asks the hand to open
        arm.update(world.read(), dt)
        world.time += dt
    assert arm.phase is Phase.RELEASE, arm.phase
    world.tcp[:3, 3] += (0.0, 0.010, 0.018)  # drawn up and across: the -y jaw's tip 6 mm over the cap's top
    board = world.ctx.blackboard
    board.release, board.cap = False, CapGrip()  # the hand has opened; a fresh grip waits for the arm's contact
    readings, pressed = world.read(), 0.0
    while world.time < 30.0 and arm.phase is not Phase.PINCH and pressed < 1.0:
        v = arm.update(readings, dt).arm.twist[:3]
        moved = world.tcp[:3, 3] + v * dt
        blocked = any(_in_cap(tip, skirt=0.0) for tip in world.tips(moved))
        world.force = -ON_TOP * v / max(float(np.linalg.norm(v)), 1e-9) if blocked else np.zeros(3)
        pressed = pressed + dt if blocked else 0.0
        if not blocked:
            world.tcp[:3, 3] = moved
        world.time += dt
        readings = world.read()
    assert arm.phase is Phase.PINCH and arm.tally.pinches == 2, (arm.phase, pressed, world.tcp[:3, 3])
    assert np.linalg.norm(world.tcp[:3, 3] - start) < 0.002, world.tcp[:3, 3]  # round the cap where it pinched


def test_a_motor_grip_twisted_off_the_caps_axis_gives_way_and_keeps_both_jaws_on_the_cap() -> None:
    """The Baxter's PyBullet trials 4 and 5 at the fresh seed 57731 (docs/unscrew-campaign.md):
    the jaws pinched the cap with the hand 11 mm off its axis across their width, which the
    motor's one force cannot see. Twisting about its own axis, the hand swung the cap's
    centre along the jaws' line: one jaw drove into it at 20-31 N and forced the jaws open
    to their stop, and 10 and 7 twists took the cap off against 4. Here the cap turns only
    about its own axis; a jaw pressed by it reads PUSH at the wrist along their line. Now
    the arm gives way to that push: the cap's axis stays within 1.5 mm of the jaws' middle
    (on main 5 mm, past the 3.8 mm to their stop), and the twist ends turned."""
    across = 0.011  # m: the hand's grasp centre from the cap's axis, across the jaws' width
    world = ScriptedJaws("baxter", "left", (-across, 0.0, TOP), gap=0.0676)
    arm, dt = world.arm, world.info.control_period
    arm.start(world.read())
    world.ctx.blackboard.cap = CapGrip(pinched=True, holding=True)
    hand = world.info.hand
    left, right = hand.pad_surfaces(np.zeros(len(hand.open)))[:2, :3, 3]
    line = (left - right) / np.linalg.norm(left - right)  # the jaws' line, hand frame
    worst = 0.0  # m: the largest offset of the cap's axis from the jaws' middle, along their line, while twisting
    while world.time < 5.0 and arm.phase in (Phase.PINCH, Phase.TWIST):
        rotation = world.tcp[:3, :3]
        along = rotation @ line
        off = -float((world.tcp[:3, 3] + rotation @ arm.grasp_centre) @ along)  # the axis from the jaws' middle
        if arm.phase is Phase.TWIST:
            worst = max(worst, abs(off))
        world.gap = 2.0 * RADIUS + 2.0 * abs(off) - 0.0005  # the jaws squeeze the cap, one pushed back by it
        world.force = np.sign(off) * PUSH * along if abs(off) > 0.0005 else np.zeros(3)
        twist = arm.update(world.read(), dt).arm.twist
        world.tcp[:3, 3] += twist[:3] * dt
        turn = float(np.linalg.norm(twist[3:]))
        if turn > 0.0:
            world.tcp[:3, :3] = axis_rotation(twist[3:] / turn, turn * dt) @ rotation
        world.time += dt
    assert arm.phase is Phase.PULL and arm.tally.twists == 1, arm.phase  # turned TWIST_ANGLE
    assert worst < 0.5 * arm.room and worst < 0.0015, (worst, arm.room)  # both jaws on the cap, short of their stop


def _close_on_nothing(robot: str, seconds: float) -> CapGrip:
    """The unscrew's jaws of `robot`, told the arm is over the cap, closing where no cap is:
    each tick the jaws stand where the hand last commanded them, no further than their stop
    (a force command drives them there). What they say of the cap after `seconds`."""
    factory = create(robot)
    info = robot_info(load_description(robot, None))
    mapping = factory.map_node(State(name="unscrew_cap", type=StateType.UNSCREW, object_size=2 * RADIUS), None)
    ctx = Context(info=info, params={})
    hand = build_controller(mapping.hand, "hand", ctx)
    closed, opened = float(info.hand.closed[0]), float(info.hand.open[0])
    q, dt = opened, 0.005
    hand.start(_jaw_readings(info, q, 0.0))
    ctx.blackboard.contact = True
    for tick in range(int(seconds / dt)):
        command = hand.update(_jaw_readings(info, q, tick * dt), dt).hand
        value = float(command.values[0])
        q = closed if command.modes[0].value == "force" else float(np.clip(value, *sorted((closed, opened))))
    return ctx.blackboard.cap


def _jaw_readings(info, q: float, time: float) -> Readings:
    n = len(info.arm_joints)
    return Readings(time=time, arm_q=np.zeros(n), arm_dq=np.zeros(n), arm_effort=np.zeros(n),
                    hand_q=np.array([q]), hand_dq=np.zeros(1), hand_effort=np.zeros(1), tcp=np.eye(4),
                    wrench=np.zeros(6), taxels={}, pad_force=np.zeros(len(info.hand.pads)), range=None)


def test_motor_jaws_that_close_to_their_stop_where_the_cap_was_say_they_hold_nothing() -> None:
    """The Baxter's left arm in PyBullet, Table 3.5 without the alignment (docs/unscrew-campaign.md):
    a cap freed by the twists fell out of the jaws and lay beside them; each pinch after
    closed the paddles to their stop, reopened and closed again, but their pads (no tactile
    image) were looked at only every GAP_CHECK, never while shut, so the hand never said the
    jaws were empty and the unscrew ended "cap still on" after its 40 pinches. Jaws shut to
    their stop hold nothing, whatever their pads say."""
    assert _close_on_nothing("baxter", 3.0).empty


def test_motor_jaws_that_slide_off_a_cap_pinched_on_a_chord_do_not_say_it_came_off() -> None:
    """The Baxter's left arm in PyBullet, Table 3.5 without the alignment, trial 3 at seed
    42011 (docs/unscrew-campaign.md), once its paddles said they were empty at their stop:
    the hand 13 mm off the cap's axis across the paddles, they held a chord of the cap, the
    twist gave way along their line and they slid off it, and the next pinch, from the same
    start pose, slid off to their stop; the unscrew ended "the cap came off its thread",
    the cap on it. A motor's grip that closes on nothing where it held a cap says nothing of
    the cap: the unscrew pinches again."""
    world = ScriptedJaws("baxter", "left", (-0.013, 0.0, TOP), gap=0.0676)
    arm = world.arm
    arm.start(world.read())
    _pinched_lost_and_back(world)  # the paddles held a chord of the cap and slid off it while twisting
    world.ctx.blackboard.cap = CapGrip(empty=True)  # the second pinch slides off the cap's curve to the stop
    arm.update(world.read(), world.info.control_period)
    assert arm.status is Status.RUNNING and arm.phase is Phase.RELEASE, arm.reason


def _pinched_lost_and_back(world: ScriptedJaws) -> None:
    """The hand says the jaws pinch the cap, the twist begins, they close on nothing while
    twisting, the hand opens, and the arm goes back to its start pose for a second pinch."""
    arm, dt, board = world.arm, world.info.control_period, world.ctx.blackboard
    board.cap = CapGrip(pinched=True, holding=True)
    arm.update(world.read(), dt)
    assert arm.phase is Phase.TWIST, arm.phase
    board.cap = CapGrip(empty=True)
    arm.update(world.read(), dt)
    assert arm.phase is Phase.RELEASE, arm.phase
    board.release, board.cap = False, CapGrip()  # the hand has opened
    while world.time < 20.0 and arm.phase is not Phase.PINCH:  # back to the start pose
        twist = arm.update(world.read(), dt).arm.twist
        world.tcp[:3, 3] += twist[:3] * dt
        turn = float(np.linalg.norm(twist[3:]))
        if turn > 0.0:
            world.tcp[:3, :3] = axis_rotation(twist[3:] / turn, turn * dt) @ world.tcp[:3, :3]
        world.time += dt
    assert arm.phase is Phase.PINCH and arm.tally.pinches == 2, arm.phase


def test_motor_jaws_that_held_the_cap_off_its_axis_along_their_line_return_centred_on_it() -> None:
    """The Baxter's right arm in MuJoCo, Table 3.5 with the alignment, trial 12 at the fresh
    seed 89734 (docs/unscrew-campaign.md): the pinch began 1.7 mm off the cap's axis along
    the paddles' line, which the paddles' contacts placed (their middle is their joint's),
    but under the 2 mm a taxel row's rounding allows, so the alignment left the start pose
    there. Back at it with the paddles open (3.8 mm a side round the 60 mm cap), untwisting,
    one paddle rubbed the cap at 13.5 N and turned it back 20-21 degrees of every 30: 8
    twists against 4. Now the return goes to where the paddles found the cap's axis."""
    world = ScriptedJaws("baxter", "right", (0.0, 0.0017, TOP), gap=0.0676)
    arm, dt = world.arm, world.info.control_period
    arm.start(world.read())
    axis = np.array([0.0, 0.0, TOP - 0.012])  # the paddles' contacts' middle: on the cap's axis along their line
    world.ctx.blackboard.cap = CapGrip(pinched=True, holding=True, axis=axis)
    while world.time < 10.0 and arm.phase is not Phase.RELEASE:  # twists, stalls (the script does not turn the hand)
        arm.update(world.read(), dt)
        world.time += dt
    assert arm.phase is Phase.RELEASE, arm.phase
    board = world.ctx.blackboard
    board.release, board.cap = False, CapGrip()  # the hand has opened; a fresh grip waits for the arm's contact
    while world.time < 20.0 and arm.phase is not Phase.PINCH:  # back to the start pose
        world.tcp[:3, 3] += arm.update(world.read(), dt).arm.twist[:3] * dt
        world.time += dt
    assert arm.phase is Phase.PINCH and arm.tally.pinches == 2, arm.phase
    for _ in range(int(1.0 / dt)):  # the paddles closing: the arm holds the start pose
        world.tcp[:3, 3] += arm.update(world.read(), dt).arm.twist[:3] * dt
        world.time += dt
    centre = world.tcp[:3, 3] + world.tcp[:3, :3] @ arm.grasp_centre
    assert abs(float(centre[1])) < 0.0006, centre  # the paddles' middle on the cap's axis along their line


def test_tactile_jaws_pinching_from_a_caps_top_that_close_on_nothing_do_not_say_it_came_off() -> None:
    """The Melfa's PyBullet trial 4 at seed 33156 without the alignment (docs/unscrew-campaign.md):
    the descent round the cap stopped short, a jaw on the cap's top, and without the
    alignment nothing seats it; the pads' tips pinched the cap's rim, a twist turned it by
    one pad, and a later pinch from there dragged the jaws across the top to close on
    nothing beyond. The unscrew ended "the cap came off its thread and left the pads", the
    cap on its thread. Jaws pinching from over their depth say nothing of where the cap is:
    they pinch again, and the verdict says what they felt."""
    reach = create("melfa").robot.hand_reach("open")
    world = ScriptedJaws("melfa", None, (0.0, -0.006, TOP + reach), gap=0.068)  # the -y jaw's tip on the top
    world.ctx.memory[SHORT_OF_TARGET] = np.array([0.0, 0.0, -0.012])  # the guarded descent stopped 12 mm short
    arm = world.arm
    arm.alignment, arm.max_pinches = False, 2
    arm.start(world.read())
    _pinched_lost_and_back(world)  # the pads' tips pressed the cap's rim and slid off it while twisting
    world.ctx.blackboard.cap = CapGrip(empty=True)  # the second pinch drags the jaws across the top, closing on nothing
    arm.update(world.read(), world.info.control_period)
    assert arm.status is Status.ERROR and "came off" not in arm.reason, arm.reason
    assert arm.reason.startswith("the cap not felt to come off after 2 pinches and 1 twists"), arm.reason
    assert "12 mm over their depth" in arm.reason, arm.reason
