"""Roles: a task names the arms it needs by their part in it, and says which does each state.
Mistakes are located errors (file, line, the fix); a task without roles reads as before."""

from __future__ import annotations

from pathlib import Path

from click.testing import CliRunner

from atd.cli import main
from atd.model import load_task
from atd.model.writer import task_to_xml

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _task(tmp_path: Path, body: str, name: str = "task.xml") -> Path:
    path = tmp_path / name
    path.write_text(f"<statemachine>\n{body}\n</statemachine>\n")
    return path


TWO_ROLES = """<role name="holder"/>
<role name="worker"/>
<state name="hold" type="move" role="holder"><path><position>0.1 0 0.2</position></path></state>
<state name="work" type="move" role="{worker}"><path><position>0.1 0.15 0.2</position></path></state>
<state name="done" type="success"/>
<transition origin="hold" destination="work"><success/></transition>
<transition origin="work" destination="done"><success/></transition>"""


def test_the_two_arm_example_reads_its_roles_and_who_does_each_state() -> None:
    task, found = load_task(EXAMPLES / "two_arm_hold_and_move.xml")
    assert found == []
    assert task.role_names == ("holder", "worker")
    assert {s.name: task.role_of(s) for s in task.states if not s.type.is_end} == {
        "approach": "holder", "preshape_hand": "holder", "grasp_object": "holder", "lift_object": "holder",
        "come_beside": "worker"}


def test_a_task_without_roles_has_one_unnamed_role_doing_every_state() -> None:
    task, found = load_task(EXAMPLES / "grasp_and_lift.xml")
    assert found == [] and task.roles == ()
    assert {task.role_of(s) for s in task.states} == {None}
    assert b"role" not in task_to_xml(task)


def test_a_role_used_but_not_declared_is_a_located_error_with_the_fix(tmp_path: Path) -> None:
    path = _task(tmp_path, TWO_ROLES.format(worker="wroker"))
    _, found = load_task(path)
    [problem] = [d for d in found if d.code == "ATD226"]
    assert (problem.loc.file, problem.loc.line) == (str(path), 5)
    assert "'work'" in problem.message and "'wroker'" in problem.message
    assert "worker" in problem.hint  # did you mean


def test_a_role_in_a_task_that_declares_none_says_how_to_declare_it(tmp_path: Path) -> None:
    path = _task(tmp_path, """<state name="go" type="move" role="holder"><path><position>0.1 0 0.2</position></path></state>
<state name="done" type="success"/>
<transition origin="go" destination="done"><success/></transition>""")
    _, found = load_task(path)
    [problem] = found
    assert problem.code == "ATD226" and problem.loc.line == 2
    assert '<role name="holder"/>' in problem.hint


def test_with_several_roles_a_state_must_say_which_does_it(tmp_path: Path) -> None:
    body = TWO_ROLES.format(worker="worker").replace(' role="holder">', ">", 1)
    _, found = load_task(_task(tmp_path, body))
    [problem] = [d for d in found if d.severity.value == "error"]
    assert problem.code == "ATD227" and problem.loc.line == 4 and "'hold'" in problem.message
    assert "holder, worker" in problem.hint


def test_a_role_twice_an_idle_role_and_a_role_on_an_end_state(tmp_path: Path) -> None:
    body = TWO_ROLES.format(worker="holder").replace("<state name=\"done\" type=\"success\"/>",
                                                     "<state name=\"done\" type=\"success\" role=\"holder\"/>")
    _, found = load_task(_task(tmp_path, '<role name="holder"/>\n' + body))
    codes = {(d.code, d.loc.line) for d in found}
    assert ("ATD218", 3) in codes  # the second <role name="holder"/>
    assert ("ATD103", 7) in codes  # an end state uses no arm
    _, found = load_task(_task(tmp_path, TWO_ROLES.format(worker="holder")))
    assert [(d.code, d.severity.value, d.loc.line) for d in found] == [("ATD228", "warning", 3)]


def test_a_subtask_needing_a_role_its_parent_lacks_is_located_at_the_including_state(tmp_path: Path) -> None:
    _task(tmp_path, TWO_ROLES.format(worker="worker"), "sub.xml")
    path = _task(tmp_path, """<state name="both" type="task" file="sub.xml"/>
<state name="done" type="success"/>
<transition origin="both" destination="done"><success/></transition>""")
    _, found = load_task(path)
    assert {(d.code, d.loc.file, d.loc.line) for d in found} == {("ATD226", str(path), 2)}
    assert {d.message.split("needs role ")[1].split(",")[0] for d in found} == {"'holder'", "'worker'"}


def test_roles_survive_a_round_trip(tmp_path: Path) -> None:
    task, _ = load_task(EXAMPLES / "two_arm_hold_and_move.xml")
    out = tmp_path / "again.xml"
    out.write_bytes(task_to_xml(task))
    again, found = load_task(out)
    assert found == [] and again == task and again.roles == task.roles


def test_atd_validate_reports_an_undeclared_role_in_one_located_line_and_exits_1(tmp_path: Path) -> None:
    path = _task(tmp_path, TWO_ROLES.format(worker="helper"))
    result = CliRunner().invoke(main, ["validate", str(path)])
    assert result.exit_code == 1
    assert f"{path}:5:1: error[ATD226]: state 'work' is done by role 'helper'" in result.output
    assert "Traceback" not in result.output


def test_a_subtask_runs_on_the_role_its_state_names_or_on_the_roles_it_names_itself(tmp_path: Path) -> None:
    _task(tmp_path, TWO_ROLES.format(worker="worker"), "both.xml")
    _task(tmp_path, """<state name="go" type="move"><path><position>0.1 0 0.2</position></path></state>
<state name="done" type="success"/>
<transition origin="go" destination="done"><success/></transition>""", "one.xml")
    parent = """<role name="holder"/>
<role name="worker"/>
<state name="first" type="task" file="both.xml"/>
<state name="then" type="task" file="one.xml"{role}/>
<state name="done" type="success"/>
<transition origin="first" destination="then"><success/></transition>
<transition origin="then" destination="done"><success/></transition>"""
    _, found = load_task(_task(tmp_path, parent.format(role=' role="worker"')))
    assert found == []
    _, found = load_task(_task(tmp_path, parent.format(role="")))
    assert [(d.code, d.loc.line) for d in found] == [("ATD227", 5)]
    _, found = load_task(_task(tmp_path, parent.format(role=' role="worker"').replace(
        'file="both.xml"', 'file="both.xml" role="holder"')))
    assert [(d.code, d.loc.line) for d in found] == [("ATD103", 4)]
