"""Issue 30: `atd robots new --from-urdf` under hostile URDFs. What it cannot import is one
line at the URDF's file:line, exit 1, nothing written; what it writes runs nothing from its
input when imported; reading costs time linear in the links.

A small arm of boxes (each link and joint on its own line) is the base every case edits.
"""

from __future__ import annotations

import ast
import json
import os
import random
import subprocess
import sys
import time
from pathlib import Path
from xml.sax.saxutils import quoteattr

import pytest
from click.testing import CliRunner

from atd.cli import main
from benchmarks.bench_urdf import seconds, tree
from atd.scaffold import package_files
from factories.urdf import read_urdf
from factories.urdf_tree import NAME
from tests.conftest import REPO
from tests.factories.test_urdf import PANDA

ARM = (("joint1", "0 0 1", "0 0 0.05"), ("joint2", "0 1 0", "0 0 0.38"), ("joint3", "0 1 0", "0.37 0 0"),
       ("joint4", "0 0 1", "0 0 -0.1"), ("joint5", "0 1 0", "0 0 -0.05"), ("joint6", "0 0 1", "0 0 -0.05"))
SENTINEL = "SENTINEL"
HOSTILE = [
    f'hand"; open("{SENTINEL}", "w").write("x"); X = "', f"hand'\nopen('{SENTINEL}', 'w')\n#", '"""', "'''",
    "back\\slash", "{__import__('os').system('touch " + SENTINEL + "')}", "f'{x}'", "h\u00e9\u4e2d\U0001f916",
    f"__import__('os').system('touch {SENTINEL}')", "a b", "", "x" * 10_000, "\u2028", ".hidden", "-dash",
]


def _link(name: str, box: str = "0.04 0.04 0.04", mass: str = "1", at: str = "0 0 0") -> str:
    return (f'<link name={quoteattr(name)}><inertial><mass value="{mass}"/><inertia ixx="0.01" iyy="0.01" '
            f'izz="0.01"/></inertial><collision><origin xyz="{at}"/><geometry><box size="{box}"/></geometry>'
            "</collision></link>")


def _joint(name: str, parent: str, child: str, xyz: str, kind: str = "revolute", axis: str = "0 0 1",
           limit: str = 'effort="50" velocity="2" lower="-2.9" upper="2.9"') -> str:
    return (f'<joint name={quoteattr(name)} type="{kind}"><parent link={quoteattr(parent)}/>'
            f'<child link={quoteattr(child)}/><origin xyz="{xyz}"/><axis xyz="{axis}"/><limit {limit}/></joint>')


def robot(hand: str = "hand", finger_joint: str = "finger_left_joint", arm_joints: int = 6, extra: str = "") -> str:
    """A 6-DOF arm of boxes (more joints: `arm_joints`) with a parallel jaw, one element a line."""
    lines = ['<robot name="small">', _link("base", "0.1 0.1 0.1", "4")]
    joints = list(ARM) + [(f"extra{k}", "0 0 1", "0 0 -0.01") for k in range(arm_joints - len(ARM))]
    parent = "base"
    for k, (joint, axis, xyz) in enumerate(joints, 1):
        lines += [_link(f"link{k}"), _joint(joint, parent, f"link{k}", xyz, axis=axis)]
        parent = f"link{k}"
    lines += [_link(hand, "0.04 0.12 0.03", "0.5", "0 0 0.015"),
              f'<joint name="hand_weld" type="fixed"><parent link="{parent}"/><child link={quoteattr(hand)}/>'
              '<origin xyz="0 0 -0.02" rpy="3.14159265 0 0"/></joint>']
    for side, sign in (("left", 1), ("right", -1)):
        name = finger_joint if side == "left" else "finger_right_joint"
        lines += [_link(f"finger_{side}", "0.02 0.01 0.05", "0.05", "0 0 0.025"),
                  _joint(name, hand, f"finger_{side}", f"0 {sign * 0.01} 0.03", "prismatic", f"0 {sign} 0",
                         'effort="20" velocity="0.2" lower="0" upper="0.04"')]
    return "\n".join([*lines, extra, "</robot>"])


def _new(tmp_path: Path, urdf: Path, name: str = "gizmo") -> tuple[int, str]:
    result = CliRunner().invoke(main, ["robots", "new", name, "--from-urdf", str(urdf),
                                       "-o", str(tmp_path / f"atd-{name}")])
    return result.exit_code, result.output


def _refused(tmp_path: Path, text: str, line: int | None, message: str) -> None:
    """`text` as a URDF is refused in one line at `line` naming `message`, and nothing is written."""
    urdf = tmp_path / "robot.urdf"
    urdf.write_text(text)
    code, output = _new(tmp_path, urdf)
    where = f"{urdf}:{line}: " if line is not None else f"{urdf}: "
    assert code == 1 and where in output and message in output, output
    assert len(output.strip().splitlines()) == 1, output
    assert sorted(p.name for p in tmp_path.iterdir()) == ["robot.urdf"]


def _line(text: str, containing: str) -> int:
    return next(k for k, line in enumerate(text.split("\n"), 1) if containing in line)


def _edit(containing: str, old: str, new: str) -> tuple[str, int]:
    """The robot with `old` made `new` on the line holding `containing`, and that line."""
    lines = robot().split("\n")
    k = _line(robot(), containing) - 1
    assert old in lines[k]
    lines[k] = lines[k].replace(old, new, 1)
    return "\n".join(lines), k + 1


def test_the_small_arm_itself_is_accepted(tmp_path):
    path = tmp_path / "robot.urdf"
    path.write_text(robot())
    assert [link.name for link in read_urdf(path).links][:2] == ["base", "link1"]


@pytest.mark.parametrize("name", HOSTILE)
@pytest.mark.parametrize("kind", ["link", "joint"])
def test_a_name_that_is_not_plain_is_refused_at_its_line(tmp_path, kind, name):
    text = robot(hand=name) if kind == "link" else robot(finger_joint=name)
    line = _line(text, "<link name=" + quoteattr(name) if kind == "link" else "<joint name=" + quoteattr(name))
    _refused(tmp_path, text, line, f"the {kind} name " if name else f"a <{kind}> has no name")
    assert not (tmp_path / SENTINEL).exists()


def test_a_seeded_sample_of_random_names_is_refused_or_plain(tmp_path):
    rng = random.Random(30)
    alphabet = "\"'\\\n{}()_.-aZ9 \u00e9#;="
    for _ in range(20):
        name = "".join(rng.choice(alphabet) for _ in range(rng.randrange(1, 12)))
        path = tmp_path / "robot.urdf"
        path.write_text(robot(hand=name))
        try:
            model = read_urdf(path)
        except ValueError as exc:
            assert str(exc).startswith(f"{path}:{_line(robot(hand=name), '<link name=' + quoteattr(name))}: ")
            assert "\n" not in str(exc)
        else:
            assert NAME.fullmatch(name) and name in [link.name for link in model.links]


@pytest.mark.parametrize("inside_a_package", [False, True])
def test_a_hostile_path_is_written_as_a_literal_and_the_package_imports_running_nothing(tmp_path, monkeypatch,
                                                                                        inside_a_package):
    """The URDF's folder and file names carry quotes, newlines, braces and calls; the link and
    joint names are plain but unusual. The package is written, and importing it (as `atd
    robots` does) neither creates the sentinel file nor fails."""
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr("factories.home.STARTS", 1)  # the arm's home is its middle posture: one search, not eight
    top = tmp_path / "hostpkg" if inside_a_package else tmp_path
    folder = top / f'q"\'\\{{x}}"""\u00e9\U0001f916 __import__("os").system("touch {SENTINEL}"); open("{SENTINEL}", "w")\n#'
    folder.mkdir(parents=True)
    if inside_a_package:
        (top / "__init__.py").write_text("")
        monkeypatch.syspath_prepend(str(tmp_path))
    urdf = folder / "r'\"\"\"\n{SENTINEL}.urdf"
    urdf.write_text(robot(hand="hand.v2-a", finger_joint="grip-1.left"))
    code, output = _new(tmp_path, urdf)
    assert code == 0, output
    package = tmp_path / "atd-gizmo"
    for source in package.rglob("*.py"):
        tree = ast.parse(source.read_text())
        for node in ast.walk(tree):
            if isinstance(node, ast.Constant) and isinstance(node.value, str):
                node.value = ""
        assert SENTINEL not in ast.unparse(tree), source  # input text only ever inside string literals
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(REPO), str(package), str(tmp_path)])}
    shown = subprocess.run([sys.executable, "-c", "import json, atd_gizmo.factory as f, atd_gizmo.description as d; "
                            "print(json.dumps([str(d.URDF), d.HAND_ROOT, d.FINGERS[0], f.LEFT]))"],
                           cwd=tmp_path, env=env, capture_output=True, text=True, timeout=120)
    assert shown.returncode == 0, shown.stderr
    assert json.loads(shown.stdout) == [str(urdf.resolve()), "hand.v2-a", "grip-1.left", "tactile_left"]
    assert not (tmp_path / SENTINEL).exists() and not (folder / SENTINEL).exists()


@pytest.mark.parametrize(("containing", "old", "new", "message"), [
    ('"link2"', 'mass value="1"', 'mass value="nan"', 'value="nan" is not finite'),
    ('"link2"', 'mass value="1"', 'mass value="inf"', 'value="inf" is not finite'),
    ('"link2"', 'mass value="1"', 'mass value="-1"', "link 'link2' has a mass of -1 kg; give its mass in kg, above 0"),
    ('"link2"', 'mass value="1"', 'mass value="0"', "link 'link2' has a mass of 0 kg; give its mass in kg, above 0"),
    ('"link2"', '<mass value="1"/>', "", "the <inertial> of link 'link2', which a joint moves, has no <mass>"),
    ('"link2"', '<inertia ixx="0.01" iyy="0.01" izz="0.01"/>', "", "link 'link2', which a joint moves, has no <inertia>"),
    ('"link2"', 'ixx="0.01"', 'ixx="-0.01"', "principal moments (-0.01, 0.01, 0.01 kg m^2) are not all above 0"),
    ('"link2"', 'ixx="0.01"', 'ixx="0"', "are not all above 0"),
    ('"link2"', 'izz="0.01"', 'izz="0.05"', "(0.01, 0.01, 0.05 kg m^2) no rigid body has"),
    ('"link2"', 'box size="0.04 0.04 0.04"', 'box size="0.04 0 0.04"', "a <box> of link 'link2' has size=\"0.04 0 0.04\""),
    ('"link2"', 'box size="0.04 0.04 0.04"', 'box size="0.04 nan 0.04"', 'size="0.04 nan 0.04" is not three numbers'),
    ('"joint2"', 'effort="50"', 'effort="0"', 'effort="0" is not above 0'),
    ('"joint2"', 'velocity="2"', 'velocity="-2"', 'velocity="-2" is not above 0'),
    ('"joint2"', 'lower="-2.9"', 'lower="-inf"', 'lower="-inf" is not finite'),
    ('"joint2"', 'lower="-2.9"', 'lower="3"', "joint 'joint2' has lower 3 >= upper 2.9"),
    ('"joint2"', 'xyz="0 0 0.38"', 'xyz="0 nan 0.38"', 'xyz="0 nan 0.38" is not three numbers'),
    ('"joint2"', "</joint>", '<dynamics damping="-1"/></joint>', 'damping="-1" is below 0'),
])
def test_numbers_a_simulator_cannot_take_are_refused_at_their_line(tmp_path, containing, old, new, message):
    text, line = _edit(containing, old, new)
    _refused(tmp_path, text, line, message)


def test_a_link_without_inertial_on_a_moving_joint_is_refused_at_the_link(tmp_path):
    text, line = _edit('"link3"', _link("link3")[len('<link name="link3">'):-len("</link>")],
                       "<collision><geometry><box size=\"0.04 0.04 0.04\"/></geometry></collision>")
    _refused(tmp_path, text, line, "link 'link3' moves on joint 'joint3' but has no <inertial>")


@pytest.mark.parametrize(("extra", "at", "message"), [
    (_link("stray"), '"stray"', "link 'stray' is a second root: no joint hangs it from another link, as none hangs "
     "'base' (line 2); a URDF is one tree"),
    ("\n".join([_link("a"), _link("b"), _joint("ab", "a", "b", "0 0 0"), _joint("ba", "b", "a", "0 0 0")]),
     '"ba"', "link 'a' hangs from a loop of joints (a <- b <- a): the root 'base' does not reach it"),
    ("\n".join([_link("a"), _joint("aa", "a", "a", "0 0 0")]), '"aa"', "link 'a' hangs from a loop of joints (a <- a)"),
    (_joint("back", "finger_left", "base", "0 0 0"), '"back"', "the URDF has no root link"),
    (_joint("again", "link1", "link3", "0 0 0"), '"again"', "link 'link3' is the child of two joints, 'joint3' and "
     "'again'"),
    (_joint("nowhere", "link1", "ghost", "0 0 0"), '"nowhere"', "joint 'nowhere' has no <child link=...> naming a link"),
    (_link("link2"), '"link2"', "a second link 'link2' (the first at line 5)"),
    (_joint("joint2", "link6", "spare", "0 0 0") + "\n" + _link("spare"), 'name="joint2" type="revolute"><parent '
     'link="link6"', "a second joint 'joint2' (the first at line 6)"),
])
def test_a_link_left_out_of_the_tree_is_refused_at_its_line(tmp_path, extra, at, message):
    text = robot(extra=extra)
    line = max(k for k, row in enumerate(text.split("\n"), 1) if at in row)  # the added element, after any original
    _refused(tmp_path, text, line, message)


def test_more_links_than_atd_imports_are_refused_at_the_first_too_many(tmp_path):
    own = robot().count("<link ")
    text = robot(extra="\n".join(_link(f"spare{k}") for k in range(1000)))
    _refused(tmp_path, text, _line(text, f'"spare{1000 - own}"'),
             f"the URDF has {own + 1000} <link>s, more than the 1000 atd imports")


def test_an_arm_of_more_than_32_joints_is_refused_at_the_33rd(tmp_path):
    text = robot(arm_joints=40)
    _refused(tmp_path, text, _line(text, 'joint name="extra26"'),
             "the arm down to 'hand' has 40 moving joints, more than the 32 atd drives")


@pytest.mark.parametrize(("text", "line", "message"), [
    ('<?xml version="1.0"?>\n<!DOCTYPE r [<!ENTITY a "aaaaaaaa"><!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;">]>\n'
     '<robot name="&b;"/>', 2, "the URDF declares a DOCTYPE or an entity; remove the declaration"),
    ('<robot name="x">\n<link name="a\x00"/></robot>', 2, "not well-formed XML"),
    ("<robot>" + "<a>" * 300 + "</a>" * 300 + "</robot>", 1, "not well-formed XML"),
    (" " * (17 * 1024 * 1024), None, "cannot read the URDF"),
])
def test_bombs_and_huge_files_are_refused_within_seconds(tmp_path, text, line, message):
    started = time.perf_counter()
    _refused(tmp_path, text, line, message)
    assert time.perf_counter() - started < 2.0


def _seconds_to_read(tmp_path: Path, links: int) -> float:
    """The best of three reads (CPU time) of a binary tree of `links` links: one slowed by
    another process would fake a quadratic cost."""
    path = tmp_path / f"tree{links}.urdf"
    path.write_text(tree(links))
    assert len(read_urdf(path).links) == links
    return seconds(path, 3)[0]


def test_reading_costs_time_linear_in_the_links(tmp_path):
    small, big = _seconds_to_read(tmp_path, 100), _seconds_to_read(tmp_path, 1000)
    assert big < 30 * small, (small, big)  # ten times the links; a quadratic reader costs a hundred times


def test_regenerating_the_shipped_panda_gives_its_arm_hand_base_and_home():
    """plugins/panda was made by `atd robots new panda --from-urdf` on pybullet_data's Panda,
    then given identified inertias; what the generator writes from the URDF is unchanged.
    (tests/cli/test_robots_new.py runs `atd robots test` on this package in both engines.)"""
    from atd_panda import description as shipped

    source = package_files("panda", "parallel_jaw", PANDA)["atd_panda/description.py"]
    written = {target.id: node.value for node in ast.parse(source).body if isinstance(node, ast.Assign)
               for target in node.targets if isinstance(target, ast.Name)}
    for name in ("ARM_JOINTS", "HAND_ROOT", "FINGERS", "MAX_OPENING", "HOME"):
        assert ast.literal_eval(written[name]) == getattr(shipped, name), name
    assert ast.unparse(written["BASE"]) == f"Origin(({shipped.BASE.xyz[0]}, 0.0, 0.0))"
