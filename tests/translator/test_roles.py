"""Translation binds a task's roles to the robot's arms: each state is mapped on its role's
arm, the ESTD says which; a robot with too few arms is refused with the reason, at the role."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from atd.cli import main
from atd.model import load_task
from atd.model.estd_xml import estd_to_xml, parse_estd
from factories.registry import create
from translator import translate

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "two_arm_hold_and_move.xml"
HOLDER = ("approach", "preshape_hand", "grasp_object", "lift_object")


def _arms(estd) -> dict[str, str | None]:
    return {s.name: s.robot_arm for s in estd.states if not s.type.is_end}


def test_baxter_binds_the_holder_to_its_chosen_arm_and_the_worker_to_the_other() -> None:
    task, _ = load_task(EXAMPLE)
    estd = translate(task, create("baxter")).estd
    assert estd.roles == {"holder": "right", "worker": "left"}
    assert _arms(estd) == {**dict.fromkeys(HOLDER, "right"), "come_beside": "left"}
    assert estd.arms == ("right", "left")
    estd = translate(task, create("baxter", "left")).estd
    assert estd.roles == {"holder": "left", "worker": "right"}


def test_tombatossals_maps_each_role_on_its_own_hand() -> None:
    task, _ = load_task(EXAMPLE)
    result = translate(task, create("tombatossals"), roles={"holder": "left"})
    estd = result.estd
    assert estd.roles == {"holder": "left", "worker": "right"}
    grasp = estd.states_by_name["grasp_object"]
    # The holder's grasp is the SDH2's (left), not the Barrett's the robot's default arm has.
    one_arm = translate(load_task(EXAMPLE.with_name("grasp_and_lift.xml"))[0], create("tombatossals", "left")).estd
    assert grasp.hand == one_arm.states_by_name["grasp_object"].hand
    assert grasp.arm == one_arm.states_by_name["grasp_object"].arm
    assert estd.states_by_name["come_beside"].robot_arm == "right"
    assert all("(left arm)" in d.message for d in result.diagnostics if "preshape_hand" in d.message)


def test_the_role_bindings_survive_the_estd_file() -> None:
    task, _ = load_task(EXAMPLE)
    estd = translate(task, create("tombatossals")).estd
    again, found = parse_estd(estd_to_xml(estd), "t.estd.xml")
    assert found == [] and again == estd and again.roles == {"holder": "right", "worker": "left"}


def test_a_one_arm_robot_is_refused_at_the_role_it_has_no_arm_for() -> None:
    task, _ = load_task(EXAMPLE)
    for robot in ("melfa", "panda"):
        result = translate(task, create(robot))
        assert result.estd is None
        [problem] = result.diagnostics
        assert problem.code == "TRN005" and (problem.loc.file, problem.loc.line) == (str(EXAMPLE), 13)
        assert f"{robot}: cannot give role 'worker' an arm: the {robot} has 1 arm (main)" in problem.message
        assert "needs 2 (holder, worker)" in problem.message and "2 arms" in problem.hint


def test_a_binding_asked_for_a_role_or_arm_that_is_not_there_is_a_usage_error(tmp_path: Path) -> None:
    task, _ = load_task(EXAMPLE)
    with pytest.raises(ValueError, match="the task has no role 'helper'"):
        translate(task, create("baxter"), roles={"helper": "left"})
    result = CliRunner().invoke(main, ["translate", str(EXAMPLE), "-r", "baxter", "--role", "worker=middle",
                                       "-o", str(tmp_path / "t.xml")])
    assert result.exit_code == 2 and not (tmp_path / "t.xml").exists()
    assert result.output.strip() == ("error: --role: role binding worker=middle: the baxter has no arm 'middle' "
                                     "(its arms: right, left)")


def test_atd_translate_binds_a_role_as_asked_and_says_so(tmp_path: Path) -> None:
    out = tmp_path / "t.xml"
    result = CliRunner().invoke(main, ["translate", str(EXAMPLE), "-r", "tombatossals", "--role", "holder=left",
                                       "-q", "-o", str(out)])
    assert result.exit_code == 0
    assert result.output.strip() == f"wrote {out} (tombatossals, holder on left, worker on right)"


def test_atd_translate_for_melfa_exits_4_and_writes_nothing(tmp_path: Path) -> None:
    out = tmp_path / "t.estd.xml"
    result = CliRunner().invoke(main, ["translate", str(EXAMPLE), "--robot", "melfa", "-o", str(out)])
    assert result.exit_code == 4 and not out.exists()
    assert f"{EXAMPLE}:13:3: error[TRN005]: melfa: cannot give role 'worker' an arm" in result.output
    assert "Traceback" not in result.output


def test_atd_check_says_which_robots_have_the_arms_and_why_the_others_not() -> None:
    result = CliRunner().invoke(main, ["check", str(EXAMPLE), "--format", "json"])
    assert result.exit_code == 0
    columns = json.loads(result.output)["tasks"][0]["robots"]
    assert {label for label, cell in columns.items() if cell["translatable"]} == {
        "baxter:right", "baxter:left", "tombatossals:right", "tombatossals:left"}
    assert "the melfa has 1 arm (main)" in columns["melfa"]["errors"][0]


def test_a_subtask_is_mapped_on_the_arm_of_its_role(tmp_path: Path) -> None:
    (tmp_path / "one.xml").write_text("""<statemachine>
<state name="go" type="move"><path><position>0.1 0.15 0.2</position></path></state>
<state name="done" type="success"/>
<transition origin="go" destination="done"><success/></transition>
</statemachine>""")
    (tmp_path / "task.xml").write_text("""<statemachine>
<role name="holder"/>
<role name="worker"/>
<state name="hold" type="move" role="holder"><path><position>0.1 0 0.2</position></path></state>
<state name="then" type="task" file="one.xml" role="worker"/>
<state name="done" type="success"/>
<transition origin="hold" destination="then"><success/></transition>
<transition origin="then" destination="done"><success/></transition>
</statemachine>""")
    task, found = load_task(tmp_path / "task.xml")
    assert found == []
    estd = translate(task, create("baxter")).estd
    sub = estd.states_by_name["then"].machine
    assert sub.states_by_name["go"].robot_arm == "left" and estd.states_by_name["hold"].robot_arm == "right"
    assert estd.arms == ("right", "left")


def test_the_task_drawings_say_which_role_and_arm_does_each_state() -> None:
    from atd.graph.model import from_estd, from_task

    task, _ = load_task(EXAMPLE)
    boxes = {n.id: n.lines for n in from_task(task, str(EXAMPLE)).nodes}
    assert "role: worker" in boxes["come_beside"] and "role: holder" in boxes["grasp_object"]
    drawn = from_estd(translate(task, create("baxter")).estd, "t.estd.xml")
    assert "holder on right, worker on left" in drawn.title
    assert "worker on the left arm" in {n.id: n.lines for n in drawn.nodes}["come_beside"]
