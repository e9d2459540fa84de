"""Every check of `atd validate` on a small file: its code, and the line it points at."""

import pytest

from atd.model import Severity

HEAD = "<statemachine>\n"
OK_END = (
    '  <state name="done" type="success"/>\n'
    '  <state name="failed" type="failure"/>\n'
)


GIVE_UP = '  <transition origin="go" destination="failed"><timeout>9</timeout></transition>\n'


def task(states: str, transitions: str = "", extra: str = "", root: str = "<statemachine>") -> str:
    """A task around the lines under test: a 'go' state, end states 'done' and 'failed'."""
    return f"{root}\n{extra}{states}{OK_END}{transitions}{GIVE_UP}</statemachine>\n"


MOVE = '  <state name="go" type="move"><path><position>0.1 0 0.2</position></path></state>\n'
GO_DONE = '  <transition origin="go" destination="done"><success/></transition>\n'
HERE = "<!--here-->"  # marks the line a diagnostic must point at


def bad(line: str) -> str:
    """One line of a case, marked as the place the diagnostic must name."""
    return line.rstrip("\n") + HERE + "\n"


SUB = '  <transition origin="sub" destination="done"><success/></transition>\n' \
      '  <transition origin="go" destination="sub"><error/></transition>\n'

CASES = {
    "unknown element with hint": ("ATD101", task(MOVE + bad('  <stat name="x" type="move"/>'), GO_DONE)),
    "unknown property in state": ("ATD101", task(
        '  <state name="go" type="move">\n' + bad("    <hand_shap>open</hand_shap>") +
        '    <path><position>0.1 0 0.2</position></path>\n  </state>\n', GO_DONE)),
    "unknown event": ("ATD101", task(MOVE, '  <transition origin="go" destination="done">\n' +
                                     bad("    <sucess/>") + "  </transition>\n")),
    "missing state name": ("ATD102", task(MOVE + bad('  <state type="move"/>'), GO_DONE)),
    "task state without file": ("ATD102", task(MOVE + bad('  <state name="sub" type="task"/>'), GO_DONE + SUB)),
    "unknown attribute": ("ATD103", task(bad('  <state name="go" type="move" speed="2">'
                                             "<path><position>0.1 0 0.2</position></path></state>"), GO_DONE)),
    "bad hand shape": ("ATD104", task('  <state name="go" type="move">\n' + bad("    <hand_shape>pinch</hand_shape>") +
                                      "    <path><position>0.1 0 0.2</position></path>\n  </state>\n", GO_DONE)),
    "bad movement": ("ATD104", task(bad('  <state name="go" type="move"><movement>fast</movement>'
                                        "<path><position>0.1 0 0.2</position></path></state>"), GO_DONE)),
    "bad state type": ("ATD104", task(MOVE + bad('  <state name="x" type="lift"/>'), GO_DONE)),
    "bad object class": ("ATD104", task(MOVE, GO_DONE, "  <object>\n" + bad("    <class>cube</class>") + "  </object>\n")),
    "position with two numbers": ("ATD105", task(
        bad('  <state name="go" type="move"><path><position>0.1 0</position></path></state>'), GO_DONE)),
    "pose with 15 numbers": ("ATD105", task(MOVE, GO_DONE, "  <object>\n" +
                                            bad("    <pose>1 0 0 0 0 1 0 0 0 0 1 0 0 0 0</pose>") + "  </object>\n")),
    "size count for a cylinder": ("ATD105", task(MOVE, GO_DONE, "  <object>\n    <class>cylinder</class>\n" +
                                                 bad("    <size>0.1 0.1 0.1</size>") + "  </object>\n")),
    "not a number": ("ATD106", task(MOVE, GO_DONE, "  <object>\n" + bad("    <weight>heavy</weight>") + "  </object>\n")),
    "non-rigid pose": ("ATD107", task(MOVE, GO_DONE, "  <object>\n" +
                                      bad("    <pose>2 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1</pose>") + "  </object>\n")),
    "zero timeout": ("ATD108", task(MOVE, GO_DONE + '  <transition origin="go" destination="failed">\n\n' +
                                    bad("    <timeout>0</timeout>") + "  </transition>\n")),
    "negative timeout": ("ATD108", task(MOVE, GO_DONE + bad('  <transition origin="go" destination="failed">'
                                                            "<timeout>-3</timeout></transition>"))),
    "negative weight": ("ATD108", task(MOVE, GO_DONE, "  <object>\n" + bad("    <weight>-1</weight>") + "  </object>\n")),
    "hand opening out of range": ("ATD108", task(
        MOVE + bad('  <state name="open" type="release"><hand_opening>1.5</hand_opening></state>'), GO_DONE)),
    "repeated property": ("ATD109", task(
        bad('  <state name="go" type="move"><movement>free</movement><movement>guarded</movement>'
            "<path><position>0.1 0 0.2</position></path></state>"), GO_DONE)),
    "wrong root": ("ATD110", task(MOVE, GO_DONE, root="<statemachin>" + HERE).replace("</statemachine>", "</statemachin>")),
    "content in an empty event": ("ATD111", task(MOVE, '  <transition origin="go" destination="done">\n' +
                                                 bad("    <success>yes</success>") + "  </transition>\n")),
    "duplicate state name": ("ATD201", task(MOVE + bad(MOVE.replace("0.1 0 0.2", "0.2 0 0.2")), GO_DONE)),
    "transition to unknown state": ("ATD202", task(MOVE, GO_DONE + bad('  <transition origin="go" destination="fail">'
                                                                       "<error/></transition>"))),
    "transition from unknown state": ("ATD202", task(MOVE, GO_DONE + bad('  <transition origin="og" destination="done">'
                                                                         "<error/></transition>"))),
    "transition with no event": ("ATD203", task(MOVE, GO_DONE + bad('  <transition origin="go" destination="failed">'
                                                                    "</transition>"))),
    "no success end state": ("ATD204", HEAD.rstrip() + HERE + "\n" + MOVE + '  <state name="failed" type="failure"/>\n'
                             '  <transition origin="go" destination="failed"><success/></transition>\n</statemachine>\n'),
    "end state with outgoing transition": ("ATD205", task(MOVE, GO_DONE + '  <transition origin="done" destination="go">'
                                                          "<success/></transition>\n").replace(
        '<state name="done" type="success"/>', '<state name="done" type="success"/>' + HERE)),
    "dead end": ("ATD206", task(MOVE + bad('  <state name="stuck" type="grasp"/>'),
                                GO_DONE + '  <transition origin="go" destination="stuck"><grasp_stable/></transition>\n')),
    "unreachable state": ("ATD207", task(MOVE + bad('  <state name="orphan" type="grasp"/>'),
                                         GO_DONE + '  <transition origin="orphan" destination="done"><success/></transition>\n')),
    "no end reachable": ("ATD208", task(
        MOVE + bad('  <state name="a" type="grasp"/>') + '  <state name="b" type="release"/>\n',
        GO_DONE + '  <transition origin="go" destination="a"><error/></transition>\n'
        '  <transition origin="a" destination="b"><success/></transition>\n'
        '  <transition origin="b" destination="a"><success/></transition>\n')),
    "ambiguous transitions": ("ATD209", task(MOVE, GO_DONE + bad('  <transition origin="go" destination="failed">'
                                                                 "<success/></transition>"))),
    "motion primitive without target": ("ATD210", task(bad('  <state name="go" type="transport"/>'), GO_DONE)),
    "sub-task file missing": ("ATD211", task(MOVE + bad('  <state name="sub" type="task" file="nowhere.xml"/>'),
                                             GO_DONE + SUB)),
    "sub-task includes itself": ("ATD212", task(MOVE + bad('  <state name="sub" type="task" file="task.xml"/>'),
                                                GO_DONE + SUB)),
    "object mesh missing": ("ATD215", task(MOVE, GO_DONE, bad("  <object>") + "    <shape>mug.stl</shape>\n  </object>\n")),
    "unknown initial state": ("ATD213", task(MOVE, GO_DONE, root='<statemachine initial="start">' + HERE)),
    "repeated transition": ("ATD214", task(MOVE, GO_DONE + bad(GO_DONE))),
}


def marked_line(xml: str) -> int:
    return next(n for n, line in enumerate(xml.splitlines(), 1) if HERE in line)


@pytest.mark.parametrize("case", sorted(CASES), ids=str)
def test_each_check_reports_its_code_at_the_right_line(case, diagnose):
    code, xml = CASES[case]
    line = marked_line(xml)
    found = diagnose(xml)
    assert (code, line) in {(d.code, d.loc.line) for d in found}, [d.render() for d in found]


def test_all_problems_are_reported_at_once(diagnose):
    xml = task(
        '  <state name="go" type="move"><hand_shape>pinch</hand_shape><movement>fast</movement>'
        '<path><position>0.1 0</position></path></state>\n',
        GO_DONE + '  <transition origin="go" destination="nowhere"><error/></transition>\n',
    )
    codes = sorted(d.code for d in diagnose(xml))
    assert codes == ["ATD104", "ATD104", "ATD105", "ATD202", "ATD210"]


def test_misspellings_get_a_did_you_mean_hint(diagnose):
    found = diagnose(task('  <state name="go" type="move"><hand_shape>pinch_grasp_prehsape</hand_shape>'
                          '<path><position>0.1 0 0.2</position></path></state>\n', GO_DONE))
    assert found[0].hint == "did you mean 'pinch_grasp_preshape'?"
    found = diagnose(task(MOVE, '  <transition origin="go" destination="dnoe"><success/></transition>\n'))
    assert any(d.hint == "did you mean 'done'?" for d in found)


def test_column_points_at_the_tag(diagnose):
    found = diagnose(task(MOVE, GO_DONE, "  <object><weight>x</weight></object>\n"))
    weight = next(d for d in found if d.code == "ATD106")
    assert (weight.loc.line, weight.loc.col) == (2, 11)


def test_multi_line_tag_is_located_at_its_first_line(diagnose):
    found = diagnose(task(MOVE, '  <transition\n     origin="go"\n     destination="nowhere">\n'
                                '    <success/>\n  </transition>\n'))
    unknown = next(d for d in found if d.code == "ATD202")
    assert (unknown.loc.line, unknown.loc.col) == (5, 3)


def test_warnings_alone_leave_the_task_valid(diagnose):
    found = diagnose(task('  <state name="go" type="transport"/>\n', GO_DONE))
    assert [d.severity for d in found] == [Severity.WARNING]


def test_sub_task_problems_are_reported_in_the_sub_task_file(atd_file, diagnose):
    sub = task(MOVE, GO_DONE + bad('  <transition origin="go" destination="failed"><timeout>-1</timeout></transition>'))
    atd_file(sub, name="sub.xml")
    found = diagnose(task(MOVE + '  <state name="sub" type="task" file="sub.xml"/>\n',
                          GO_DONE + '  <transition origin="sub" destination="done"><success/></transition>\n'
                          '  <transition origin="go" destination="sub"><error/></transition>\n'))
    assert [(d.code, d.loc.file.endswith("sub.xml"), d.loc.line) for d in found] == [("ATD108", True, marked_line(sub))]


def test_mutual_inclusion_is_caught(atd_file, diagnose):
    body = MOVE + '  <state name="sub" type="task" file="{}"/>\n'
    edges = GO_DONE + ('  <transition origin="sub" destination="done"><success/></transition>\n'
                       '  <transition origin="go" destination="sub"><error/></transition>\n')
    atd_file(task(body.format("a.xml"), edges), name="b.xml")
    found = diagnose(task(body.format("b.xml"), edges), name="a.xml")
    assert [(d.code, d.loc.file.endswith("b.xml")) for d in found] == [("ATD212", True)]


def test_initial_attribute_chooses_the_first_state(atd_file):
    from atd.model import load_task
    path = atd_file(task(MOVE + '  <state name="first" type="move"><path><position>0 0 0.2</position></path></state>\n',
                         GO_DONE + '  <transition origin="first" destination="go"><success/></transition>\n',
                         root='<statemachine initial="first">'))
    loaded, found = load_task(path)
    assert loaded.initial_state == "first" and found == []


def test_comments_anywhere_are_ignored(atd_file):
    """A comment inside a list of numbers or between a transition's events is not part of the task."""
    from atd.model import load_task
    path = atd_file(task('  <state name="go" type="move"><!-- reach --><path><position>0.1 <!-- x --> 0 0.2</position>'
                         '</path></state>\n',
                         '  <transition origin="go" destination="done"><!-- a --><success/><!-- b --></transition>\n'))
    loaded, found = load_task(path)
    assert found == [] and loaded.states_by_name["go"].target.values == (0.1, 0.0, 0.2)
    assert [e.type.value for e in loaded.transitions[0].events] == ["success"]


def test_a_huge_name_or_text_is_repeated_shortened(diagnose):
    """Ten megabytes of input in a diagnostic would be ten megabytes on the terminal."""
    name = "x" * 3_000_000
    found = diagnose(task(MOVE, GO_DONE + f'  <transition origin="go" destination="{name}"><error/></transition>\n'
                                          f'  <transition origin="{name}y" destination="done"><error/></transition>\n'))
    assert [d.code for d in found] == ["ATD202", "ATD202"]
    assert all(len(d.render()) < 300 and "(3,000,00" in d.message for d in found), found[0].render()[:300]
    found = diagnose(task('  <state name="go" type="move"><hand_shape>' + "ab " * 1_000_000 + "</hand_shape>"
                          "<path><position>0.1 0 0.2</position></path></state>\n", GO_DONE))
    assert [d.code for d in found] == ["ATD104"] and len(found[0].render()) < 2_500
    assert found[0].message.endswith("characters in all)")
