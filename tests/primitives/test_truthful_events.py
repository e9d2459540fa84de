"""Issue 10, events that tell the truth: a primitive stopped short does not end in success,
and a task that reports success has done what it says (judged here by the simulator's
ground truth, which the robot never sees)."""

from __future__ import annotations

from pathlib import Path

from atd.model import load_task
from atd.sim import load_description, make_robot
from atd.sim.scene import scene_from_task
from factories.registry import create
from tests.primitives.conftest import EXAMPLES, execute, last_reasons, run_example
from translator import translate

DATA = Path(__file__).resolve().parents[1] / "data"


def test_a_melfa_place_straight_after_the_grasp_does_not_succeed_with_the_box_unmoved() -> None:
    """It once ended in success 55 ms in, on the grip force settling, the box unmoved. Now
    it succeeds only with the box standing on the table where the path puts it (a firm grip
    drags it there), and otherwise stops short on the box's resistance, an error."""
    outcome, executor, robot = run_example(DATA / "place_after_grasp.xml")
    x, y, z = robot.object_pose()[:3, 3]
    if outcome.succeeded:
        assert abs(x - 0.10) < 0.01 and abs(y - 0.05) < 0.01 and z < 0.03, f"succeeded with the box at {x, y, z}"
    else:
        assert last_reasons(executor)[0].startswith("stopped short: contact"), last_reasons(executor)


def test_the_sdh2_puts_the_box_down_on_the_table_before_letting_go() -> None:
    """The place used to end on the wrist reading the hand speed up (5 N) with the box
    11 cm above the table, which then fell onto its target when the hand opened."""
    heights = {}

    def watch(robot, path: str, time: float) -> None:
        heights.setdefault(path, robot.object_pose()[2, 3])

    outcome, _, _ = run_example(EXAMPLES / "pick_and_place.xml", watch, robot="tombatossals", arm="left")
    assert outcome.succeeded, outcome.summary
    assert heights["let_go"] < 0.03, f"the box stood at z = {heights['let_go']:.3f} when the hand opened"


def test_the_naive_grasp_on_the_barrett_succeeds_only_with_the_cylinder_lifted() -> None:
    """The naive grasp's lift once stopped on a 17 N contact 20 ms in and counted it as
    success, the cylinder left on the table: a guarded transport stopped short is an error."""
    path = EXAMPLES / "grasp_and_lift.xml"
    task, _ = load_task(path)
    estd = translate(task, create("tombatossals", "right", grasp="naive")).estd
    robot = make_robot(load_description("tombatossals", "right"), scene_from_task(task, path))
    outcome, _ = execute(estd, robot, task=task)
    lifted = robot.object_pose()[2, 3] > 0.12
    assert outcome.succeeded == lifted, f"{outcome.summary}; cylinder at z = {robot.object_pose()[2, 3]:.3f}"


def test_a_lift_the_grip_cannot_carry_is_not_a_stable_grasp() -> None:
    """The pads slide up a slippery 3 kg cylinder, still pressing, while it stays on the
    table: the lift once reported success and grasp_stable; the wrist never feels the
    weight, so grasp_stable does not hold and the lift ends on its timeout."""
    outcome, executor, robot = run_example(DATA / "lift_too_heavy.xml")
    assert robot.object_pose()[2, 3] < 0.045  # ground truth: it never left the table
    assert not outcome.succeeded, outcome.summary
    assert [r["event"] for r in executor.trace.records if r["type"] == "event"][-1] == "timeout"


def test_a_lift_whose_object_drops_out_once_the_arm_stops_is_not_a_success() -> None:
    """The Barrett's pinch on the preset's mug (PyBullet, the approach error, trial 11): the
    lift reached its target with the pads at 2.1 N and said success; the pads eased to 1.2 N
    and the mug fell out 1.6 s later, in the judge's hold (a false success at 1593679). The
    lift now holds the object still at its target for 2 s before it says success."""
    from tests.primitives.conftest import preset_trials

    [record] = preset_trials((11,), robot="tombatossals", arm="right", engine="pybullet", grasp="robust",
                             object="mug", perturbation="approach")
    assert record.task_succeeded == record.judged_succeeded, (record.summary, record.judge_reason)
