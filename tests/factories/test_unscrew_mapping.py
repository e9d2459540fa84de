"""The unscrew state (thesis 3.3.6) in the ATD language: validated, translated on the hands
that pinch with fingers of their own and on the grippers (the jaws grip the cap, the last
wrist joint twists it), its alignment switched off from the ATD, and refused with the
reason where the wrist cannot turn one twist."""

from __future__ import annotations

import subprocess
import sys
from dataclasses import replace
from functools import cached_property

import pytest

from atd.model import load_task
from atd.model.estd_xml import read_estd
from factories.description import RobotDescription
from factories.registry import create
from tests.conftest import EXAMPLES
from translator import translate

UNSCREW = """
    <statemachine>
      <object name="bottle">
        <pose>1 0 0 0.10  0 1 0 0.10  0 0 1 0.09  0 0 0 1</pose>
        <weight>0.3</weight>
        <class>cylinder</class>
        <size>0.035 0.18</size>
      </object>
      <state name="unscrew_cap" type="unscrew" object="bottle">
        <object_size>0.03</object_size>
        {parameter}
      </state>
      <state name="opened" type="success"/>
      <state name="stuck" type="failure"/>
      <transition origin="unscrew_cap" destination="opened"><success/></transition>
      <transition origin="unscrew_cap" destination="stuck"><error/></transition>
      <transition origin="unscrew_cap" destination="stuck"><timeout>120</timeout></transition>
    </statemachine>"""


def atd(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "atd", *args], capture_output=True, text=True, timeout=300)


@pytest.mark.parametrize("arm", ["right", "left"])
def test_both_tombatossals_hands_unscrew_with_the_thesis_defaults(atd_file, arm: str) -> None:
    task, found = load_task(atd_file(UNSCREW.format(parameter="")))
    assert found == [], found
    [state] = [s for s in translate(task, create("tombatossals", arm=arm)).estd.states if s.name == "unscrew_cap"]
    assert state.primitive == "unscrew" and state.arm.name == "unscrew_arm" and state.hand.name == "unscrew_hand"
    arm_params, hand = state.arm.params, state.hand.params
    assert (arm_params["twist_angle"], arm_params["torque_limit"], arm_params["pull_force_limit"],
            arm_params["cap_removed_distance"], arm_params["alignment"]) == (30.0, 10.0, 7.0, 0.04, True)
    assert (hand["grasp_shape"], hand["grasp_force"], hand["finger_min_distance"]) == ("pinch_grasp", 5.0, 0.012)


def test_the_reactive_alignment_is_switched_off_from_the_atd(atd_file, tmp_path) -> None:
    path = atd_file(UNSCREW.format(parameter='<parameter name="alignment">false</parameter>'))
    out = tmp_path / "task.estd.xml"
    result = atd("translate", str(path), "--robot", "tombatossals", "--arm", "left", "-o", str(out))
    assert result.returncode == 0, result.stderr
    [state] = [s for s in read_estd(out)[0].states if s.name == "unscrew_cap"]
    assert state.arm.params["alignment"] is False


@pytest.mark.parametrize(("robot", "arm", "source"),
                         [("melfa", None, "tactile"), ("panda", None, "tactile"), ("baxter", "left", "motor"),
                          ("baxter", "right", "motor")])
def test_a_gripper_grips_the_cap_and_twists_it_with_its_last_wrist_joint(atd_file, robot: str, arm: str | None,
                                                                          source: str) -> None:
    task, _ = load_task(atd_file(UNSCREW.format(parameter="")))
    [state] = [s for s in translate(task, create(robot, arm=arm)).estd.states if s.name == "unscrew_cap"]
    assert state.primitive == "unscrew" and state.arm.name == "unscrew_arm" and state.hand.name == "unscrew_jaws"
    arm_params, hand = state.arm.params, state.hand.params
    assert (arm_params["twist_angle"], arm_params["torque_limit"], arm_params["pull_force_limit"],
            arm_params["cap_removed_distance"], arm_params["alignment"]) == (30.0, 10.0, 7.0, 0.04, True)
    assert arm_params["wrist_turn"] in (1.0, -1.0)  # its last joint rolls the hand about the approach
    assert arm_params["cap_width"] == 0.03  # the task's object_size: the jaws' room round the cap is searched for
    assert (hand["grasp_force"], hand["finger_min_distance"], hand["force_source"]) == (5.0, 0.012, source)


def test_a_wrist_that_cannot_turn_one_twist_is_refused_with_the_reason(atd_file) -> None:
    from factories.melfa.factory import MelfaFactory

    class StiffWrist(MelfaFactory):
        """A Melfa whose last joint turns 20 degrees in all."""

        @cached_property
        def robot(self) -> RobotDescription:
            robot = super().robot
            links = tuple(replace(link, joint=replace(link.joint, lower=-0.1745, upper=0.1745))
                          if link.joint is not None and link.joint.name == robot.arm_joints[-1] else link
                          for link in robot.links)
            return replace(robot, links=links)

    path = atd_file(UNSCREW.format(parameter=""))
    result = translate(load_task(path)[0], StiffWrist())
    assert result.estd is None
    message = result.diagnostics[0].render()
    assert "error[TRN001]" in message and "the wrist joint 'j6'" in message, message
    assert "turns 20 degrees in all, less than one twist of 30 degrees" in message, message


def test_an_unscrew_state_that_names_an_unknown_object_is_a_located_error(atd_file) -> None:
    path = atd_file(UNSCREW.format(parameter="").replace('type="unscrew" object="bottle"',
                                                         'type="unscrew" object="jar"'))
    result = atd("validate", str(path))
    assert result.returncode == 1 and "error[ATD219]" in result.stdout and "task.xml:" in result.stdout, result.stdout


@pytest.mark.parametrize(("robot", "felt"), [("baxter", 8.0), ("melfa", 2.0), ("tombatossals", 2.0)])
def test_the_cap_is_felt_with_no_less_force_than_the_robots_wrist_tells_from_its_jolts(robot: str, felt: float) -> None:
    """The Baxter's virtual wrist read 2 N while descending onto nothing, 34-38 mm over the cap:
    its explore feels for its own 8 N; a robot with a real wrist sensor keeps the task's 2 N."""
    task, found = load_task(EXAMPLES / "unscrew_by_touch.xml")
    assert not found
    [state] = [s for s in translate(task, create(robot)).estd.states if s.name == "find_cap"]
    assert state.arm.params["force_threshold"] == felt
