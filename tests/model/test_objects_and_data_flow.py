"""Issue 31's language: named objects, containers, values passed between states, perceptual
primitives and their events, sub-task inputs and outcomes. One case per rule, each found at
its line with its code, as `atd validate` prints it."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from atd.model import Severity, load_task, task_to_xml
from tests.conftest import REPO

THESIS = REPO / "tests" / "data" / "empty_the_box"
HERE = "<!--here-->"  # marks the line a diagnostic must point at

BOX = ('    <container name="box"><pose>1 0 0 0.3  0 1 0 0  0 0 1 0  0 0 0 1</pose>'
       '<size>0.30 0.25 0.10</size></container>\n')
LOOK = ('  <state name="look" type="perceive" container="box"><method>vision</method>'
        '<writes name="approach" kind="pose"/></state>\n')
REACH = '  <state name="reach" type="move"><target from="approach"/></state>\n'
MUG = "  <object name=\"mug\"><pose>1 0 0 0.1  0 1 0 0  0 0 1 0.03  0 0 0 1</pose></object>\n"
DUCK = "  <object name=\"duck\"><pose>1 0 0 0.1  0 1 0 0.1  0 0 1 0.03  0 0 0 1</pose></object>\n"
ENDS = '  <state name="done" type="success"/>\n  <state name="failed" type="failure"/>\n'


def edge(origin: str, destination: str, events: str = "<success/>") -> str:
    return f'  <transition origin="{origin}" destination="{destination}">{events}</transition>\n'


def task(body: str, initial: str = "look", box: bool = True) -> str:
    env = f"  <environment>\n{BOX}  </environment>\n" if box else ""
    return f'<statemachine initial="{initial}">\n{env}{body}{ENDS}</statemachine>\n'


def bad(line: str) -> str:
    return line.rstrip("\n") + HERE + "\n"


MOVE_DONE = '  <state name="go" type="move"><path><position>0 0 0.2</position></path></state>\n' + edge("go", "done")
GRASP_MUG = '  <state name="go" type="grasp" object="mug"/>\n' + edge("go", "done")
FOUND_THEN_REACH = LOOK + REACH + edge("look", "reach", "<object_found/>") + edge("look", "done", "<nothing_found/>") \
    + edge("reach", "done")
CASES = {
    # several objects
    "an unnamed object among several": ("ATD102", task(bad("  <object><weight>0.1</weight></object>") + MUG + GRASP_MUG,
                                                       "go")),
    "two objects with one name": ("ATD218", task(MUG + bad(MUG) + GRASP_MUG, "go")),
    "an object name that is not a plain name": ("ATD113", task(bad('  <object name="my mug"/>') +
                                                              '  <state name="go" type="grasp"/>\n' + edge("go", "done"),
                                                              "go")),
    "an unknown object": ("ATD219", task(MUG + DUCK + bad('  <state name="go" type="grasp" object="cup"/>') +
                                         edge("go", "done"), "go")),
    "no object said among several": ("ATD220", task(MUG + DUCK + bad('  <state name="go" type="grasp"/>') +
                                                    edge("go", "done"), "go")),
    "a move without path among several objects": ("ATD220", task(
        MUG + DUCK + bad('  <state name="go" type="move"/>') + edge("go", "done"), "go")),
    "an end state acting on an object": ("ATD103", task(
        MUG + '  <state name="go" type="grasp"/>\n' + bad('  <state name="over" type="success" object="mug"/>') +
        edge("go", "done") + edge("go", "over", "<error/>"), "go")),
    # containers
    "two containers with one name": ("ATD218", task(f"  <environment>\n{BOX}{bad(BOX)}  </environment>\n" + LOOK +
                                                    edge("look", "done", "<nothing_found/>") +
                                                    edge("look", "failed", "<object_found/>"), box=False)),
    "a container without a size": ("ATD102", task(
        '  <environment>\n' + bad('    <container name="box"><pose>1 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1</pose>')
        + "    </container>\n  </environment>\n" + MOVE_DONE, "go", box=False)),
    "a container of no size": ("ATD108", task(
        '  <environment>\n    <container name="box"><pose>1 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1</pose>\n' +
        bad("      <size>0 0.2 0.1</size>") + "    </container>\n  </environment>\n" + MOVE_DONE, "go", box=False)),
    "walls that leave no room": ("ATD108", task(
        '  <environment>\n    <container name="box"><pose>1 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1</pose>'
        "<size>0.3 0.2 0.1</size>\n" + bad("      <wall>0.1</wall>") + "    </container>\n  </environment>\n" +
        MOVE_DONE, "go", box=False)),
    "an infinite container size": ("ATD106", task(
        '  <environment>\n    <container name="box"><pose>1 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1</pose>\n' +
        bad("      <size>inf 0.2 0.1</size>") + "    </container>\n  </environment>\n" + MOVE_DONE, "go", box=False)),
    "an unknown container": ("ATD219", task(
        bad('  <state name="look" type="perceive" container="crate"><method>vision</method></state>') +
        edge("look", "done", "<nothing_found/>") + edge("look", "failed", "<object_found/>"))),
    # perceptual primitives
    "a perceive without a method": ("ATD102", task(
        bad('  <state name="look" type="perceive" container="box"/>') + edge("look", "done", "<nothing_found/>"))),
    "a perceive without a container": ("ATD102", task(
        bad('  <state name="look" type="perceive"><method>vision</method></state>') +
        edge("look", "done", "<nothing_found/>"))),
    "an unknown method": ("ATD104", task(
        '  <state name="look" type="perceive" container="box">\n' + bad("    <method>sonar</method>") + "  </state>\n"
        + edge("look", "done", "<nothing_found/>"))),
    "a direction that is no unit vector": ("ATD108", task(
        '  <state name="feel" type="explore">\n' + bad("    <direction>0 0 -2</direction>") + "  </state>\n" +
        edge("feel", "done", "<contact/>") + edge("feel", "failed", "<no_contact/>"), "feel")),
    "an explore without a direction": ("ATD102", task(
        bad('  <state name="feel" type="explore"/>') + edge("feel", "done", "<contact/>"), "feel")),
    "a direction on a move": ("ATD103", task(
        bad('  <state name="go" type="move"><direction>0 0 -1</direction><path><position>0 0 0.2</position></path>'
            '</state>') + edge("go", "done"), "go")),
    "an object_found leaving a move": ("ATD223", task(
        MOVE_DONE + '  <transition origin="go" destination="failed">\n' + bad("    <object_found/>") +
        "  </transition>\n", "go")),
    "a contact leaving a perceive": ("ATD223", task(
        LOOK + edge("look", "done", "<nothing_found/>") + '  <transition origin="look" destination="failed">\n' +
        bad("    <contact/>") + "  </transition>\n")),
    # values
    "a grasp that writes": ("ATD114", task(
        bad('  <state name="go" type="grasp"><writes name="n" kind="count"/></state>') + edge("go", "done"), "go")),
    "an explore that writes a pose": ("ATD114", task(
        bad('  <state name="feel" type="explore"><direction>0 0 -1</direction><writes name="p" kind="pose"/></state>')
        + edge("feel", "done", "<contact/>"), "feel")),
    "an unknown value kind": ("ATD104", task(
        '  <state name="look" type="perceive" container="box"><method>vision</method>\n' +
        bad('    <writes name="approach" kind="vector"/>') + "  </state>\n" + edge("look", "done", "<nothing_found/>"))),
    "a value name that is not a plain name": ("ATD113", task(
        '  <state name="look" type="perceive" container="box"><method>vision</method>\n' +
        bad('    <writes name="the approach" kind="pose"/>') + "  </state>\n" + edge("look", "done", "<nothing_found/>"))),
    "a path and a target": ("ATD109", task(
        '  <state name="go" type="move"><path><position>0 0 0.2</position></path>\n' + bad('    <target from="a"/>') +
        "  </state>\n" + edge("go", "done"), "go")),
    "a target on a grasp": ("ATD103", task(bad('  <state name="go" type="grasp"><target from="a"/></state>') +
                                           edge("go", "done"), "go")),
    "a target offset of two numbers": ("ATD105", task(
        LOOK + '  <state name="reach" type="move">\n' + bad('    <target from="approach" offset="0 0.05"/>') +
        "  </state>\n" + edge("look", "reach", "<object_found/>") + edge("look", "done", "<nothing_found/>") +
        edge("reach", "done"))),
    "a path for the hand's lowest point without a hand shape": ("ATD102", task(
        '  <state name="go" type="move">\n' + bad('    <path for="lowest_point"><position>0 0 0.2</position></path>') +
        "  </state>\n" + edge("go", "done"), "go")),
    "a path for an unknown point of the hand": ("ATD104", task(
        '  <state name="go" type="move"><hand_shape>closed</hand_shape>\n' +
        bad('    <path for="fingertip"><position>0 0 0.2</position></path>') + "  </state>\n" + edge("go", "done"),
        "go")),
    "a value read that nothing writes": ("ATD221", task(
        bad(REACH) + edge("reach", "done"), "reach")),
    "a value read after perceive found nothing": ("ATD221", task(
        LOOK + bad(REACH) + edge("look", "reach", "<nothing_found/>") + edge("look", "done", "<object_found/>") +
        edge("reach", "done"))),
    "a value read on one way in but not another": ("ATD221", task(
        '  <state name="start" type="move"><path><position>0 0 0.2</position></path></state>\n' + LOOK + bad(REACH) +
        edge("start", "look") + edge("start", "reach", "<error/>") + edge("look", "reach", "<object_found/>") +
        edge("look", "done", "<nothing_found/>") + edge("reach", "done"), "start")),
    "a count as a target": ("ATD222", task(
        '  <state name="look" type="perceive" container="box"><method>vision</method>'
        '<writes name="approach" kind="count"/></state>\n' + bad(REACH) + edge("look", "reach", "<object_found/>") +
        edge("look", "done", "<nothing_found/>") + edge("reach", "done"))),
    "one value of two kinds": ("ATD222", task(
        LOOK + '  <state name="feel" type="explore"><direction>0 0 -1</direction>\n' +
        bad('    <writes name="approach" kind="point"/>') + "  </state>\n" + edge("look", "feel", "<object_found/>") +
        edge("look", "done", "<nothing_found/>") + edge("feel", "done", "<contact/>") +
        edge("feel", "failed", "<no_contact/>"))),
    "an object top on a move": ("ATD103", task(
        bad('  <state name="go" type="move"><path><position>0 0 0.2</position></path><object_top from="a"/></state>')
        + edge("go", "done"), "go")),
    "an object top that is a number": ("ATD103", task(
        '  <state name="go" type="grasp">\n' + bad("    <object_top>0.05</object_top>") + "  </state>\n" +
        edge("go", "done"), "go")),
    "an object top read that nothing writes": ("ATD221", task(
        bad('  <state name="go" type="grasp"><object_top from="approach"/></state>') + edge("go", "done"), "go")),
    "a point as an object top": ("ATD222", task(
        '  <state name="feel" type="explore"><direction>0 0 -1</direction><writes name="p" kind="point"/></state>\n'
        + bad('  <state name="go" type="grasp"><object_top from="p"/></state>') + edge("feel", "go", "<contact/>") +
        edge("feel", "failed", "<no_contact/>") + edge("go", "done"), "feel")),
    # outcomes
    "an outcome without a name": ("ATD102", task(
        MOVE_DONE + '  <transition origin="go" destination="failed">\n' + bad("    <outcome/>") + "  </transition>\n",
        "go")),
    "an outcome leaving a move": ("ATD223", task(
        MOVE_DONE + '  <transition origin="go" destination="failed">\n' + bad('    <outcome name="placed"/>') +
        "  </transition>\n", "go")),
}


def marked_line(xml: str) -> int:
    return next(n for n, line in enumerate(xml.splitlines(), 1) if HERE in line)


@pytest.mark.parametrize("case", sorted(CASES), ids=str)
def test_each_rule_reports_its_code_at_the_right_line(case, diagnose):
    code, xml = CASES[case]
    found = diagnose(xml)
    assert (code, marked_line(xml)) in {(d.code, d.loc.line) for d in found}, [d.render() for d in found]


def test_the_thesis_task_validates_and_its_values_flow_into_the_sub_task() -> None:
    """Fig. 3.24: perceive, take one out, perceive again, until nothing is found."""
    task, found = load_task(THESIS / "empty_the_box.xml")
    assert found == []
    assert list(task.containers) == ["box"] and task.containers["box"].inner_size == pytest.approx((0.28, 0.23, 0.09))
    look = task.states_by_name["look"]
    assert (look.method.value, look.container, [(v.name, v.kind.value) for v in look.writes]) == \
        ("vision", "box", [("approach", "pose"), ("seen", "count")])
    assert task.states_by_name["take_one_out"].inputs == {"approach": "approach"}
    sub, found = load_task(THESIS / "pick_and_place.xml")
    assert found == [] and [(v.name, v.kind.value) for v in sub.inputs] == [("approach", "pose")]
    assert sub.states_by_name["reach"].target_from == "approach"


def test_named_objects_are_an_ordered_mapping_and_states_say_which_they_act_on(atd_file) -> None:
    path = atd_file(task(DUCK + MUG + GRASP_MUG + edge("go", "failed", "<error/>"), "go", box=False))
    loaded, found = load_task(path)
    assert found == []
    assert list(loaded.objects) == ["duck", "mug"] and loaded.objects["mug"].pose.position == (0.1, 0.0, 0.03)
    assert loaded.object is loaded.objects["duck"] and loaded.states_by_name["go"].object == "mug"


def test_one_unnamed_object_stays_valid_and_is_the_object(diagnose, atd_file) -> None:
    path = atd_file(task("  <object><weight>0.2</weight></object>\n" + '  <state name="go" type="grasp"/>\n' +
                         edge("go", "done") + edge("go", "failed", "<error/>"), "go", box=False))
    loaded, found = load_task(path)
    assert found == [] and list(loaded.objects) == ["object"] and loaded.object.weight == 0.2


def test_the_hints_name_the_known_objects_and_the_states_that_could_write(diagnose) -> None:
    found = {d.code: d for d in diagnose(task(MUG + DUCK + '  <state name="go" type="grasp" object="cup"/>\n' +
                                              edge("go", "done"), "go"))}
    assert found["ATD219"].hint == "the task's objects: mug, duck"
    xml = CASES["a value read on one way in but not another"][1]
    flow = next(d for d in diagnose(xml) if d.code == "ATD221")
    assert flow.message == ("state 'reach' reads 'approach', which is not written on every way to it: "
                            "start -> reach writes it nowhere")
    assert flow.hint.startswith("'look' writes it when it leaves on <object_found/>")


def test_a_value_written_on_every_way_in_is_fine_loops_included(diagnose) -> None:
    """The thesis loop: after the sub-task, perceive again; the value is written anew each round."""
    loop = FOUND_THEN_REACH.replace(edge("reach", "done"), edge("reach", "look") + edge("reach", "failed", "<error/>"))
    assert diagnose(task(loop)) == []


def test_a_sub_task_outcome_must_be_one_of_its_end_states(atd_file) -> None:
    atd_file((THESIS / "pick_and_place.xml").read_text(), "pick_and_place.xml")
    parent = (THESIS / "empty_the_box.xml").read_text().replace('<outcome name="missed"/>', '<outcome name="mised"/>')
    _, found = load_task(atd_file(parent))
    (d,) = [d for d in found if d.severity is Severity.ERROR]
    assert (d.code, d.loc.line, d.hint) == ("ATD224", 33, "its outcomes (end states): placed, missed")


def test_sub_task_inputs_are_given_once_each_and_only_those(atd_file) -> None:
    atd_file((THESIS / "pick_and_place.xml").read_text(), "pick_and_place.xml")
    text = (THESIS / "empty_the_box.xml").read_text()
    binding = '<input name="approach" from="approach"/>'
    _, found = load_task(atd_file(text.replace(binding, "")))
    assert [(d.code, d.message) for d in found] == [
        ("ATD225", "state 'take_one_out' gives sub-task 'pick_and_place.xml' no input 'approach'")]
    _, found = load_task(atd_file(text.replace(binding, binding + '<input name="speed" from="seen"/>')))
    assert [(d.code, d.message, d.hint) for d in found] == [
        ("ATD225", "sub-task 'pick_and_place.xml' of state 'take_one_out' has no input 'speed'", "its inputs: approach")]


def test_a_sub_task_input_of_another_kind_is_an_error(atd_file) -> None:
    atd_file((THESIS / "pick_and_place.xml").read_text(), "pick_and_place.xml")
    text = (THESIS / "empty_the_box.xml").read_text().replace('from="approach"', 'from="seen"')
    _, found = load_task(atd_file(text))
    assert [(d.code, d.loc.line) for d in found] == [("ATD222", 23)]
    assert "gives input 'approach' (a pose) the value 'seen', a count" in found[0].message


def test_the_new_language_survives_a_round_trip(tmp_path) -> None:
    for name in ("empty_the_box.xml", "pick_and_place.xml"):
        original, _ = load_task(THESIS / name)
        copy = tmp_path / name
        copy.write_bytes(task_to_xml(original))
        assert load_task(copy)[0] == original


def test_the_seen_top_a_grasp_reads_is_read_written_and_translated(tmp_path) -> None:
    """examples/pick_one.xml's grasp aims its close at the top the approach saw."""
    from atd.model.estd_xml import estd_to_xml, parse_estd
    from factories.registry import create
    from translator import translate

    original, found = load_task(REPO / "examples" / "pick_one.xml")
    assert not found and original.states_by_name["grasp"].top_from == "approach"
    copy = tmp_path / "copy.xml"
    copy.write_bytes(task_to_xml(original))
    assert load_task(copy)[0] == original
    estd = translate(original, create("melfa")).estd
    read, problems = parse_estd(estd_to_xml(estd), "x.estd.xml")
    assert not problems and read.states_by_name["grasp"].top_from == "approach"


def test_a_target_offset_is_read_written_and_translated_with_its_value(tmp_path) -> None:
    """examples/unscrew_by_touch.xml pinches a known depth under the cap top an explore felt."""
    from atd.model.estd_xml import estd_to_xml, parse_estd
    from factories.registry import create
    from translator import translate

    original, found = load_task(REPO / "examples" / "unscrew_by_touch.xml")
    assert not found
    assert original.states_by_name["around_cap"].target_from == "cap_top"
    assert original.states_by_name["around_cap"].target_offset == (0.0, 0.0, -0.012)
    copy = tmp_path / "copy.xml"
    copy.write_bytes(task_to_xml(original))
    assert load_task(copy)[0] == original
    estd = translate(original, create("tombatossals", "left")).estd
    read, problems = parse_estd(estd_to_xml(estd), "x.estd.xml")
    assert not problems and read.states_by_name["carry_cap"].target_offset == (0.0, -0.15, 0.1)


def test_a_path_for_the_hand_s_lowest_point_is_read_and_written(tmp_path) -> None:
    """examples/free_one.xml drags the hand's lowest point at heights over the box's floor."""
    original, found = load_task(REPO / "examples" / "free_one.xml")
    assert not found
    assert {name: original.states_by_name[name].path_for.value for name in ("over", "drag", "tip_tall")} == \
        {"over": "hand_shape", "drag": "lowest_point", "tip_tall": "lowest_point"}
    copy = tmp_path / "copy.xml"
    copy.write_bytes(task_to_xml(original))
    assert load_task(copy)[0] == original


def test_validate_prints_located_lines_and_exits_1_without_a_traceback(atd_file) -> None:
    xml = CASES["a value read after perceive found nothing"][1]
    path = atd_file(xml)
    result = subprocess.run([sys.executable, "-m", "atd", "validate", str(path)], capture_output=True, text=True,
                            timeout=120)
    assert result.returncode == 1 and "Traceback" not in result.stderr + result.stdout
    assert f"{path}:{marked_line(xml)}:3: error[ATD221]: state 'reach' reads 'approach'" in result.stdout
