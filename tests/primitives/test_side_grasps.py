"""Side grasps (issue 32): a motion the arm cannot make ends through `error` with the
reason, never in a silent stall; what translation refuses of a grasp from the side says
which joint or link is in the way, at the state's line."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from atd.cli.check import every_robot
from atd.model import load_task
from atd.model.diagnostics import Severity
from atd.model.frames import rpy_of
from atd.model.vocabulary import EventType
from atd.sim.scene import box_scene
from tests.primitives.conftest import Stage, both_done, execute, last_reasons, leaf, machine, melfa, use
from tests.primitives.side_grasps import side_grasp, turn
from translator import translate

BEHIND = (0.0, 0.0, 0.25)  # the Melfa's TCP here, its hand turned to point along +x, needs j2 past its limit


def test_a_move_the_arm_cannot_make_ends_in_an_error_naming_the_joint() -> None:
    tilt = tuple(float(np.degrees(a)) for a in rpy_of(turn("+x")))
    # the wrist reads the turn's swing as up to 16 N: the stall, not a contact, is what this asks about
    move = use("cartesian_move", target=BEHIND, tilt=tilt, force_threshold=100.0)
    estd = machine(Stage(move, use("hold_position"), both_done(), 30.0),
                   failures={"s0": (EventType.ERROR, leaf("arm_error"))})
    outcome, executor = execute(estd, melfa(box_scene(xy=(0.0, 0.22))))
    assert not outcome.succeeded and outcome.end_state == "failed"
    assert outcome.sim_time < 12.0, f"stalled until {outcome.sim_time:.1f} s"  # the 30 s timeout never came
    reason = " ".join(last_reasons(executor))
    assert "no progress" in reason and "joint 'j2' at its lower limit" in reason, reason


@pytest.mark.parametrize("direction", ["+x", "+y", "-y"])
def test_a_refused_side_grasp_names_the_joint_or_the_link_in_the_way(tmp_path: Path, direction: str) -> None:
    path = tmp_path / "side.xml"
    path.write_text(side_grasp(direction, height=0.04))  # a 4 cm grasp: the table is in every hand's way
    task, _ = load_task(path)
    for label, factory in every_robot():
        errors = [d for d in translate(task, factory).diagnostics if d.severity is Severity.ERROR]
        assert errors, f"{label} accepted a side grasp 4 cm over the table"
        first = errors[0].render().splitlines()[0]
        robot = factory.robot
        named = [name for name in (*robot.arm_joints, *robot.hand_links) if f"'{name}'" in first or f" {name}" in first]
        assert named, f"{label}: {first}"
        assert first.startswith(f"{path}:"), first  # located in the ATD
