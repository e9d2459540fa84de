"""The unscrew's phase machine (thesis 3.3.6, Fig. 3.11) on scripted situations: the SDH2's
own hand model and the factory's parameters, driven by a scripted cap instead of physics.
The TCP follows the arm's commanded twist exactly, the fingers their references until the
cap blocks them; the pads, the wrist's torque and pull force are what the script says a
cap of that kind would make them read."""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
import pytest

from atd.model.frames import axis_rotation
from atd.model.task import State
from atd.model.vocabulary import StateType
from atd.sim import load_description
from atd.sim.simrobot import robot_info
from factories.registry import create
from primitives.arm.unscrew import UnscrewArm
from primitives.arm.unscrew_phases import Phase
from primitives.base import Context, StateView, Status
from primitives.conditions import StatusIs
from primitives.hands.extension import ExtensionGauge
from primitives.hands.unscrew import UnscrewHand
from primitives.registry import build_controller
from primitives.robot import HandMode, Readings

INFO = robot_info(load_description("tombatossals", "left"))  # the SDH2
HAND = INFO.hand
PADS = [0, 1]  # the pinch's two pads, f1 and f2
PAD_STIFFNESS = 40.0  # N a pad presses at its finger's full effort (the script's)


@dataclass
class Cap:
    """What the script makes of the cap under the hand."""

    width: float = 0.03  # m across; 0: no cap at all
    offset: tuple[float, float] = (0.0, 0.0)  # m, world x y of its axis from the grasp centre at the start
    turns_to_free: float = 1.0 / 12.0  # turns of the cap before its thread lets it go
    stuck: bool = False  # its thread does not turn: the torque grows with the twist
    weak: float = 1.0  # of its finger's push f2's pad feels (the rest on the finger's bare link)
    chatter: float = 0.0  # N the pads' readings swing about their squeeze, in turn, tick to tick (PyBullet's contacts)
    slips_out: bool = False  # once free it leaves the pads and falls away (a pinch across its axis squeezes it out)
    neck: float = 0.0  # m: once it slipped out, fingers nearer than this stop on their bare links, no pad touching
    turned: float = field(default=0.0, init=False)  # rad the cap has turned
    wound: float = field(default=0.0, init=False)  # rad this pinch has twisted a stuck cap
    seated_at: float | None = field(default=None, init=False)  # TCP height when this pinch took hold of it

    @property
    def free(self) -> bool:
        return self.turned >= 2 * np.pi * self.turns_to_free


class ScriptedRobot:
    """A TCP that moves as commanded and an SDH2 whose pinch a scripted cap blocks."""

    def __init__(self, cap: Cap) -> None:
        self.cap = cap
        self.tcp = np.eye(4)
        self.tcp[:3, :3] = np.diag([1.0, -1.0, -1.0])  # the hand points down
        self.tcp[:3, 3] = (0.5, 0.0, 0.3)
        self.q = HAND.postures["pinch_grasp_preshape"].copy()
        self.effort = np.zeros(len(self.q))
        self.gauge = ExtensionGauge(HAND, PADS, self.q)
        self.axis = self._grasp_centre()[:2] + np.asarray(cap.offset)
        self.time = 0.0
        self.touching = False
        self.forced = np.zeros(len(self.q), bool)
        self.ticks = 0

    def _grasp_centre(self) -> np.ndarray:
        return self.tcp[:3, 3] + self.tcp[:3, :3] @ np.array([0.019, 0.0, 0.0])

    def _across(self) -> float:
        """How far the cap's axis lies off the pinch line (m, across it)."""
        across_world = self.tcp[:3, :3] @ np.array([*self.gauge.across, 0.0])
        return float((np.array([*self.axis, 0.0]) - self._grasp_centre()) @ across_world)

    def _between(self, q: np.ndarray) -> bool:
        """The cap is between the pads and stops them closing past its width."""
        cap = self.cap
        return cap.width > 0.0 and abs(self._across()) < cap.width / 2 and self.gauge.gap(q) < cap.width

    def read(self) -> Readings:
        force = np.zeros(len(HAND.pads))
        taxels: dict[str, np.ndarray] = {}
        if self.touching:
            pressed = float(self.effort[1] / HAND.effort_limit[1] * PAD_STIFFNESS)
            swing = self.cap.chatter * (-1.0) ** self.ticks
            force[PADS] = (pressed + swing, pressed * self.cap.weak - swing)
            taxels = {HAND.pads[k].name: self._image(k, float(f)) for k, f in zip(PADS, force[PADS])}
        wrench = np.zeros(6)
        cap = self.cap
        if self.touching and cap.stuck:
            wrench[5] = 50.0 * cap.wound  # N m: the twist winds up against a cap that will not turn
        elif self.touching and not cap.free and cap.seated_at is not None:
            wrench[5] = 0.1  # the thread's friction
            wrench[2] = 3000.0 * max(0.0, self.tcp[2, 3] - cap.seated_at)  # N: the thread holds it down
        return Readings(time=self.time, arm_q=np.zeros(7), arm_dq=np.zeros(7), arm_effort=np.zeros(7),
                        hand_q=self.q.copy(), hand_dq=np.zeros(len(self.q)), hand_effort=self.effort.copy(),
                        tcp=self.tcp.copy(), wrench=wrench, taxels=taxels, pad_force=force, range=None)

    def _image(self, k: int, pressed: float) -> np.ndarray:
        """One lit taxel where the cap's axis crosses the pad (its side facing the cap)."""
        surface = HAND.pad_surfaces(self.q)[k]
        on_axis = np.linalg.inv(self.tcp) @ np.array([*self.axis, self.tcp[2, 3] - 0.06, 1.0])
        local = (np.linalg.inv(surface) @ on_axis)[:2]
        rows, cols = HAND.pads[k].taxels
        half = np.asarray(HAND.pads[k].half_size)
        col, row = np.clip(((local / half + 1.0) / 2.0 * (cols, rows)).astype(int), 0, (cols - 1, rows - 1))
        image = np.zeros((rows, cols))
        image[row, col] = pressed
        return image

    def step(self, arm: np.ndarray, values: np.ndarray, modes: tuple[HandMode, ...], dt: float) -> None:
        turn = arm[3:] * dt
        angle = float(np.linalg.norm(turn))
        rotation = axis_rotation(turn / angle, angle) if angle > 0.0 else np.eye(3)
        self.tcp[:3, :3] = rotation @ self.tcp[:3, :3]
        self.tcp[:3, 3] += arm[:3] * dt
        self.forced = np.array([m is HandMode.FORCE for m in modes])
        self.effort = np.where(self.forced, values, 0.3 * HAND.effort_limit)
        goal = np.where(self.forced, HAND.closed, values)
        moved = self.q + np.clip(goal - self.q, -HAND.velocity_limit * dt, HAND.velocity_limit * dt)
        cap = self.cap
        blocked = self._between(moved)
        if not blocked:
            self.q = self.q if cap.width == 0.0 and self.gauge.gap(moved) < cap.neck else moved
            cap.wound = 0.0
        elif not self.touching:
            cap.seated_at = self.tcp[2, 3]
        elif cap.stuck:
            cap.wound += abs(float(turn[2]))
        elif not cap.free:
            cap.turned += max(0.0, float(turn[2]))  # it turns with the pads, unscrewing positive about the world's z
        if cap.free and cap.slips_out:
            cap.width = 0.0
        self.touching = blocked
        self.time += dt
        self.ticks += 1


def _controllers(cap: Cap, **params) -> tuple[ScriptedRobot, UnscrewArm, UnscrewHand]:
    factory = create("tombatossals", arm="left")
    mapping = factory.map_node(State(name="unscrew_cap", type=StateType.UNSCREW, object_size=0.03), None)
    ctx = Context(info=INFO, params={})
    arm_use = mapping.arm.model_copy(update={"params": {**mapping.arm.params, **params}})
    arm = build_controller(arm_use, "arm", ctx)
    hand = build_controller(mapping.hand, "hand", ctx)
    return ScriptedRobot(cap), arm, hand


def _run(cap: Cap, seconds: float = 60.0, **params) -> tuple[ScriptedRobot, UnscrewArm, UnscrewHand]:
    robot, arm, hand = _controllers(cap, **params)
    readings = robot.read()
    arm.start(readings)
    hand.start(readings)
    dt = INFO.control_period
    while robot.time < seconds and Status.RUNNING in (arm.status,) and arm.phase is not Phase.OFF:
        arm_out, hand_out = arm.update(readings, dt), hand.update(readings, dt)
        robot.step(arm_out.arm.twist, hand_out.hand.values, hand_out.hand.modes, dt)
        readings = robot.read()
    return robot, arm, hand


def test_a_cap_that_comes_free_is_pulled_off_after_a_regrasp_on_the_pull_force() -> None:
    """Two twists of 30 degrees free it: the first pull meets the thread (PULL_FORCE_LIMIT),
    the hand opens, the arm goes back, pinches and twists again; the second pull goes 4 cm."""
    robot, arm, hand = _run(Cap(turns_to_free=55.0 / 360.0))
    assert arm.status is Status.DONE and hand.status is Status.DONE, (arm.reason, hand.reason)
    assert arm.tally.twists == 2 and "cap off after 2 twists" in arm.reason, arm.reason
    assert arm.counts == {"twists": 2}  # the count the trace carries as a number (atd.campaign.unscrew)
    assert "PULL_FORCE_LIMIT" in arm.tally.ended
    assert robot.cap.free and robot.tcp[2, 3] > 0.3 + 0.039


def test_a_stuck_cap_ends_each_twist_at_the_torque_limit_and_the_unscrew_gives_up() -> None:
    robot, arm, _ = _run(Cap(stuck=True), max_pinches=3)
    assert arm.status is Status.ERROR and arm.tally.twists == 3 and arm.counts == {"twists": 3}, arm.reason
    assert "above UNSCREW_TORQUE_LIMIT" in arm.reason, arm.reason
    assert robot.cap.turned < np.radians(30.0) / 2  # no twist got anywhere near TWIST_ANGLE


def test_fingers_closing_on_nothing_stop_at_the_min_distance_and_never_twist() -> None:
    robot, arm, _ = _run(Cap(width=0.0), max_pinches=2)
    assert arm.status is Status.ERROR and arm.tally.twists == 0, arm.reason
    assert "closed on nothing" in arm.reason, arm.reason


@pytest.mark.parametrize("alignment", [True, False])
def test_a_cap_that_comes_free_and_leaves_the_pads_ends_the_unscrew_saying_it_is_off(alignment: bool) -> None:
    """The cap comes free in the second twist and falls out of the pads (the Panda's jaws
    pinching 12-15 mm across a jam jar's cap squeezed it out, MuJoCo, docs/unscrew-campaign.md):
    the next pinch, where the pads had held it, closes on nothing. The unscrew ends there,
    saying the cap came off and was lost; it used to pinch on to `max_pinches` and say the
    cap was still on, while the judge found it off its thread, on the table."""
    robot, arm, _ = _run(Cap(turns_to_free=55.0 / 360.0, slips_out=True), alignment=alignment)
    assert robot.cap.free
    assert arm.status is Status.ERROR and arm.tally.twists == 2, arm.reason
    assert "came off its thread and left the pads" in arm.reason and "still on" not in arm.reason, arm.reason
    assert arm.tally.pinches == 3 and robot.time < 15.0, (arm.tally, robot.time)


def test_a_cap_that_comes_free_and_leaves_fingers_that_then_touch_nothing_ends_the_unscrew_saying_it_is_off() -> None:
    """The Barrett's PyBullet trial 3 at seed 33156 without the alignment (docs/unscrew-campaign.md):
    the fourth twist freed the cap, which sprang out of the pads onto the table; every pinch
    after it stopped its fingers on their bare links, over FINGER_MIN_DISTANCE apart, no pad
    touching anything, and timed out. After 36 of them the unscrew ended "cap still on". Here
    the SDH2's fingers stop 20 mm apart once the cap is out. Where the pads had held the cap,
    a pinch whose pads touch nothing says it left them."""
    robot, arm, _ = _run(Cap(turns_to_free=55.0 / 360.0, slips_out=True, neck=0.02), max_pinches=5)
    assert robot.cap.free
    assert arm.status is Status.ERROR and arm.tally.twists == 2 and arm.tally.pinches == 3, arm.reason
    assert arm.reason.startswith("the cap came off its thread and left the pads after 2 twists: pinch 3 touched "
                                 "nothing with any pad in 6 s"), arm.reason


def test_fingers_that_close_on_nothing_before_ever_holding_the_cap_pinch_again() -> None:
    """No cap was ever held: closing on nothing says nothing of a cap come off; the pinches run out."""
    robot, arm, _ = _run(Cap(width=0.0), max_pinches=3)
    assert arm.status is Status.ERROR and "the cap not felt to come off after 3 pinches" in arm.reason, arm.reason


@pytest.mark.parametrize("alignment", [True, False])
def test_a_cap_pinched_off_its_axis_moves_the_grasp_centre_onto_it(alignment: bool) -> None:
    """The cap's axis 6 mm off the pinch line: the pads' centres of pressure say so, and
    before the next pinch the start pose moves the grasp centre there (Fig. 3.12); switched
    off, the arm goes back to where it started."""
    robot, arm, _ = _run(Cap(offset=(0.006, 0.0), turns_to_free=55.0 / 360.0), alignment=alignment)
    start = arm.start_pose
    centre = start.position + start.rotation @ np.array([0.019, 0.0, 0.0])
    off = float(np.linalg.norm(centre[:2] - robot.axis))
    assert arm.status is Status.DONE, arm.reason
    if alignment:
        assert arm.tally.aligned >= 1 and off < 0.002, (arm.tally, off)  # a taxel row is 3 mm across
    else:
        assert arm.tally.aligned == 0 and off == pytest.approx(0.006, abs=1e-4), off


def test_a_finger_whose_link_stops_on_the_cap_still_centres_the_next_pinch() -> None:
    """The cap's axis 6 mm off the pinch line and f2 stopped on it by its bare link, its pad
    feeling nothing (a Barrett's near finger on an off-centre cap): f1's centre of pressure
    and f2's pad, where the cap stopped it, still place the axis, and the pinches move
    towards it. Without them the alignment had nothing and every pinch closed where the first did."""
    robot, arm, _ = _run(Cap(offset=(0.006, 0.0), weak=0.0), max_pinches=3)
    start = arm.start_pose
    centre = start.position + start.rotation @ np.array([0.019, 0.0, 0.0])
    assert arm.status is Status.ERROR and "did not all press" in arm.reason, arm.reason  # f2's pad never presses
    assert arm.tally.aligned >= 1 and float(np.linalg.norm(centre[:2] - robot.axis)) < 0.004, arm.tally


def test_a_pinch_one_pad_of_which_never_feels_the_grasp_force_is_given_up_after_pinch_time() -> None:
    """One pad reads a third of its finger's push (the finger's link also presses the jar's neck):
    the pinch never reaches the force on every pad; after PINCH_TIME the arm gives up that
    pinch, and here, its one pinch spent, the unscrew, without ever twisting."""
    robot, arm, _ = _run(Cap(weak=0.3), max_pinches=1)
    assert arm.status is Status.ERROR and arm.tally.twists == 0, arm.reason
    assert "did not all press the grasp force within 6 s" in arm.reason, arm.reason
    assert robot.time < 10.0


def test_a_pinch_whose_pads_chatter_about_the_grasp_force_twists_the_cap_off() -> None:
    """Each pad reads 1.5 N over and under its squeeze in turn, tick to tick, as a Barrett's
    pads on a cap do in PyBullet (8.7-12 N about 10 N): the pinch holds the grasp force, so it
    twists. Judged tick by tick, a pad under 90 % of the force every other tick never let it:
    the pinches ran out with the cap on (the juice bottle, 0.78 turns)."""
    robot, arm, hand = _run(Cap(turns_to_free=55.0 / 360.0, chatter=1.5), max_pinches=3)
    assert arm.status is Status.DONE and arm.tally.twists == 2, arm.reason
    assert robot.cap.free


def test_the_arm_done_condition_carries_the_unscrews_twist_count_into_the_events_evidence() -> None:
    """What the trace records of the event that ends the unscrew: the reason and, as a number
    beside it, the twists (atd.campaign.unscrew reads that, never the reason's words)."""
    done = StatusIs(Context(info=INFO, params={}), (), "arm", Status.DONE)
    view = StateView(elapsed=12.0, arm=Status.DONE, hand=Status.DONE, reasons={"arm": "cap off after 4 twists"},
                     counts={"arm": {"twists": 4}})
    assert done.holds(None, view, 0.01)
    assert done.evidence["twists"] == 4 and done.evidence["reason"] == "cap off after 4 twists"
