"""Side grasps (issue 32): what `atd check` accepts of a grasp from the side, `atd run`
does: on every robot and arm, a bottle approached 90 degrees from the side, from the left
and from the right, lifts (the simulator's truth) wherever translation accepts it, and a
refusal says which joint or link is in the way, at the state's line; a motion the arm
cannot make ends through `error` with the reason, never in a silent stall."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from atd.cli.check import every_robot
from atd.model import load_task
from atd.model.diagnostics import Severity
from atd.model.frames import rpy_of
from atd.runtime.session import Run
from atd.model.vocabulary import EventType
from atd.sim.scene import box_scene
from factories.registry import create
from tests.primitives.conftest import Stage, both_done, execute, last_reasons, leaf, machine, melfa, use
from tests.primitives.side_grasps import OBJECT, side_grasp, turn
from translator import translate

LIFTED = 0.05  # m above where it stood: the bottle has been lifted
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
        assert _refusal_names_what_is_in_the_way(first, factory), f"{label}: {first}"
        assert first.startswith(f"{path}:"), first  # located in the ATD


def _refusal_names_what_is_in_the_way(first: str, factory) -> bool:
    robot = factory.robot
    return any(f"'{name}'" in first or f" {name}" in first for name in (*robot.arm_joints, *robot.hand_links))


@pytest.mark.parametrize("direction", ["+y", "-y"])
def test_check_and_run_agree_on_side_grasps(tmp_path: Path, direction: str) -> None:
    path = tmp_path / "side.xml"
    path.write_text(side_grasp(direction))
    task, _ = load_task(path)
    for label, factory in every_robot():
        result = translate(task, factory)
        errors = [d.render().splitlines()[0] for d in result.diagnostics if d.severity is Severity.ERROR]
        if errors:
            assert _refusal_names_what_is_in_the_way(errors[0], factory), f"{label}: {errors[0]}"
            continue
        run = Run(result.estd, factory, engine="mujoco")
        outcome = run.execute()
        assert outcome.succeeded, f"{label} {direction}: check accepted, the run: {outcome.summary}"
        assert run.object_position[2] > OBJECT[2] + LIFTED, f"{label} {direction}: the bottle at {run.object_position}"


def test_the_barrett_grasps_a_bottle_from_the_side_lifts_it_and_puts_it_down_standing(tmp_path: Path) -> None:
    """The Barrett's pinch closes along its x axis, which a side turn stands upright: its
    description rolls it a quarter turn about the approach (`Hand.side_roll`), so its fingers
    close across the bottle, and check accepts the approach it comes in preshaped (open, its
    flat fingers reach into the table: refused above, naming them). The place after it keeps
    the hand turned as it holds the bottle: turned top-down first (main at 04c5919), it swung
    the bottle out of the hand, which lay on its side 25 cm away, and the place ended in
    "no surface within 0.03 m below the place target"."""
    path = tmp_path / "side.xml"
    path.write_text(side_grasp("+y", coming="pinch_grasp_preshape", put_down=True))
    task, _ = load_task(path)
    factory = create("tombatossals")  # the right arm: the Barrett
    result = translate(task, factory)
    assert not [d for d in result.diagnostics if d.severity is Severity.ERROR], result.diagnostics
    run = Run(result.estd, factory, engine="mujoco")
    highest: list[float] = [0.0]
    run.observers.append(lambda _: highest.__setitem__(0, max(highest[0], float(run.robot.object_pose()[2, 3]))))
    ends: list[np.ndarray] = []
    outcome = run.execute(afterwards=lambda sim: ends.extend((sim.object_pose(), sim.true_tcp())))
    assert outcome.succeeded, outcome.summary
    assert highest[0] > OBJECT[2] + LIFTED, highest[0]  # truth: lifted
    bottle, tcp = ends
    assert abs(float(bottle[2, 3]) - OBJECT[2]) < 0.005 and float(bottle[2, 2]) > 0.98, bottle  # truth: standing
    assert np.hypot(*(bottle[:2, 3] - OBJECT[:2])) < 0.03, bottle[:3, 3]  # where it stood
    assert abs(tcp[2, 2]) < 0.1 and abs(tcp[2, 0]) < 0.1, tcp[:3, :3]  # approach and closing axes level
