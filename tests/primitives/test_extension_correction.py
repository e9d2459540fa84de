"""D5's finger-extension check on the three-finger robust grasp (issue 10): the quality Q,
the position correction Z and the orientation correction alpha, read from where the
pads touch (the hand's forward kinematics and the tactile images)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from atd.campaign.perturbation import approach_taken
from atd.model import load_task
from atd.runtime.session import Run
from atd.sim import load_description
from atd.sim.simrobot import robot_info
from factories.registry import create
from primitives.hands.extension import ExtensionGauge
from primitives.robot import Readings
from tests.primitives.conftest import EXAMPLES
from translator import translate


def _barrett_pinch_closed_at(f1: float, f2: float) -> tuple[ExtensionGauge, Readings]:
    hand = robot_info(load_description("tombatossals", "right")).hand
    q = hand.postures["pinch_grasp"].copy()
    q[1], q[2] = f1, f2
    zeros = np.zeros(len(q))
    readings = Readings(time=0.0, arm_q=np.zeros(7), arm_dq=np.zeros(7), arm_effort=np.zeros(7), hand_q=q,
                        hand_dq=zeros, hand_effort=zeros, tcp=np.eye(4), wrench=np.zeros(6), taxels={},
                        pad_force=np.array([5.0, 5.0, 0.0, 0.0]), range=None)
    return ExtensionGauge(hand, [0, 1], hand.postures["pinch_grasp_preshape"]), readings


def test_fingers_stopped_at_equal_extensions_are_a_stable_grasp() -> None:
    gauge, readings = _barrett_pinch_closed_at(1.3, 1.3)
    check = gauge.check(readings)
    assert check.quality < 1e-6 and np.linalg.norm(check.shift) < 1e-4, check


def test_a_finger_stopped_early_moves_the_hand_towards_it() -> None:
    """F1 stands at x = -25 mm on the Barrett's palm and F2 at +25 mm; F2 stopped less closed
    than F1, so the object lies towards F2 (+x) and Z moves the hand that way."""
    gauge, readings = _barrett_pinch_closed_at(1.5, 1.1)
    check = gauge.check(readings)
    assert check.quality > 0.01, check  # D5's bound: unstable
    assert check.shift[0] > 0.005 and abs(check.shift[1]) < 1e-3, check


def _box_in_a_cylindrical_grasp(tmp_path: Path, engine: str, yaw: float) -> Run:
    """The Barrett's cylindrical grasp (F1 and F2 side by side against the thumb) on a 5 cm
    box, the approach left turned `yaw` degrees about the vertical."""
    text = (EXAMPLES / "grasp_and_lift.xml").read_text()
    text = (text.replace("pinch_grasp", "cylindrical_grasp").replace("<class>cylinder</class>", "<class>box</class>")
            .replace("<size>0.02 0.08</size>", "<size>0.05 0.05 0.08</size>"))
    path = tmp_path / "box_lift.xml"
    path.write_text(text)
    task, _ = load_task(path)
    factory = create("tombatossals", arm="right")
    estd = translate(task, factory).estd
    error = {"dx": 0.0, "dy": 0.0, "dz": 0.0, "roll": 0.0, "pitch": 0.0, "yaw": yaw}
    return Run(approach_taken(estd, error), factory, engine=engine)


@pytest.mark.parametrize("engine", ["mujoco", "pybullet"])
def test_a_box_met_at_an_angle_turns_the_hand_square_to_it(tmp_path: Path, engine: str) -> None:
    """Turned 15 degrees, F1 and F2 meet the box's face at different extensions; alpha turns
    the hand until they agree. Without the corrections the grasp ended in its error in
    MuJoCo, and in PyBullet lifted the box held 24 degrees askew."""
    run = _box_in_a_cylindrical_grasp(tmp_path, engine, 15.0)
    poses = []
    outcome = run.execute(afterwards=lambda robot: poses.extend([robot.true_tcp(), robot.object_pose()]))
    assert outcome.succeeded and run.object_position[2] > 0.04 + 0.05, (outcome.summary, run.object_position)
    assert abs(_askew(*poses)) < 8.0, _askew(*poses)  # square to a face, within 8 degrees


def _askew(hand: np.ndarray, box: np.ndarray) -> float:
    """Degrees about the vertical between the hand's axes and the nearest of the box's faces."""
    x = hand[:3, :3].T @ box[:3, 0]
    return float((np.degrees(np.arctan2(x[1], x[0])) + 45.0) % 90.0 - 45.0)
