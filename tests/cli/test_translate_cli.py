"""`atd translate`, `atd check` and `atd robots` as a user meets them: output, files, exit codes."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import textwrap
from atd.model.estd_xml import read_estd
from atd.sim import variants
from factories.registry import BUILTIN, installed
from tests.conftest import EXAMPLES, REPO
from tests.plugin_site import write_robot_package


def atd(*args: str, env=None) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "atd", *args], capture_output=True, text=True, timeout=120,
                          cwd=REPO, env=env)


def test_pick_and_place_translates_for_every_robot(tmp_path):
    for name in ("pick_and_place.xml",):
        shutil.copy(EXAMPLES / name, tmp_path / name)
    for robot in ("tombatossals", "melfa", "baxter"):
        result = atd("translate", str(tmp_path / "pick_and_place.xml"), "--robot", robot)
        assert result.returncode == 0, result.stderr
        out = tmp_path / f"pick_and_place.{robot}.estd.xml"
        assert f"wrote {out}" in result.stdout
        assert "put_down   place      " in result.stdout  # the summary table
        estd, found = read_estd(out)
        assert found == [] and estd.robot == robot
    json_out = tmp_path / "p.json"
    assert atd("translate", str(tmp_path / "pick_and_place.xml"), "-r", "melfa", "--format", "json",
               "-o", str(json_out), "-q").returncode == 0
    assert read_estd(json_out)[0] == read_estd(tmp_path / "pick_and_place.melfa.estd.xml")[0]


def test_untranslatable_exits_4_and_writes_nothing(tmp_path):
    task = tmp_path / "wipe.xml"
    task.write_text(textwrap.dedent("""\
        <statemachine>
          <state name="wipe" type="slide"><path><position>0.1 0.1 0.03</position></path></state>
          <state name="done" type="success"/>
          <transition origin="wipe" destination="done"><success/></transition>
        </statemachine>
        """))
    result = atd("translate", str(task), "--robot", "melfa")
    assert result.returncode == 4
    assert f"{task}:2:3: error[TRN001]: melfa: cannot map slide state 'wipe'" in result.stderr
    assert list(tmp_path.iterdir()) == [task]


def test_perception_translates_and_a_hand_too_wide_to_sweep_the_box_exits_4_naming_why(tmp_path):
    """Issue 31: the thesis's box-emptying task translates; the spread Barrett cannot sweep the box."""
    task = REPO / "tests" / "data" / "empty_the_box" / "empty_the_box.xml"
    assert atd("translate", str(task), "--robot", "baxter", "-o", str(tmp_path / "out.estd.xml")).returncode == 0
    spread = tmp_path / "spread.xml"
    spread.write_text((REPO / "examples" / "empty_the_box_exploration.xml").read_text().replace(
        "<method>blind_exploration</method>", "<method>blind_exploration</method><hand_shape>open</hand_shape>"))
    for sub in ("pick_one.xml", "free_one.xml", "put_out.xml", "put_down_beside.xml"):
        shutil.copy(REPO / "examples" / sub, tmp_path)
    result = atd("translate", str(spread), "--robot", "tombatossals", "--arm", "right", "-o", str(tmp_path / "x.xml"))
    assert result.returncode == 4 and "Traceback" not in result.stderr
    assert (f"{spread}:28:3: error[TRN001]: tombatossals (right arm): cannot map perceive state 'look': the Barrett "
            "BH8-280 reaches 15.9 cm sideways in its 'open' posture") in result.stderr
    assert "it could not tell a wall from an object" in result.stderr and not (tmp_path / "x.xml").exists()


def test_invalid_atd_exits_1(tmp_path):
    task = tmp_path / "bad.xml"
    task.write_text('<statemachine>\n  <state name="a" type="mvoe"/>\n</statemachine>\n')
    result = atd("translate", str(task), "--robot", "baxter")
    assert result.returncode == 1 and "error[ATD104]" in result.stderr
    assert "Traceback" not in result.stderr


def test_an_output_into_a_missing_folder_is_refused_before_any_work(tmp_path):
    """translate -o, graph -o and run --trace name the folder instead of failing with a traceback."""
    task = str(EXAMPLES / "pick_and_place.xml")
    missing = tmp_path / "no" / "such"
    for args in (("translate", task, "--robot", "melfa", "-o", str(missing / "pp.estd.xml")),
                 ("graph", task, "-o", str(missing / "pp.svg")),
                 ("run", task, "--robot", "melfa", "--trace", str(missing / "t.jsonl"), "-q")):
        result = atd(*args)
        assert result.returncode == 2, args
        assert f"the folder {missing} does not exist" in result.stderr and "Traceback" not in result.stderr
        assert not (tmp_path / "no").exists()


def test_unknown_robot_and_arm_are_usage_errors():
    result = atd("translate", str(EXAMPLES / "simple_move.xml"), "--robot", "nao")
    assert result.returncode == 2 and f"no robot 'nao' is installed; installed: {', '.join(installed())}" in result.stderr
    result = atd("translate", str(EXAMPLES / "simple_move.xml"), "--robot", "melfa", "--arm", "left")
    assert result.returncode == 2 and "robot 'melfa' has no arm 'left'; choose one of: main" in result.stderr


def test_user_config_overrides_the_robot_values(tmp_path):
    config = tmp_path / "robots.toml"
    config.write_text("[melfa.controllers.close_until_force]\ngrasp_force = 22.5\n")
    out = tmp_path / "out.xml"
    assert atd("translate", str(EXAMPLES / "pick_and_place.xml"), "-r", "melfa", "--config", str(config),
               "-o", str(out)).returncode == 0
    grasp = next(s for s in read_estd(out)[0].states if s.name == "grasp")
    assert grasp.hand.params["grasp_force"] == 22.5
    config.write_text("[melfa.controllers.cartesian_move]\ntarget = [0, 0, 0]\n")
    result = atd("translate", str(EXAMPLES / "pick_and_place.xml"), "-r", "melfa", "--config", str(config))
    assert result.returncode == 1
    assert "[melfa.controllers.cartesian_move] 'target' comes from the task" in result.stderr


def test_check_prints_the_robot_matrix_with_reasons(tmp_path):
    result = atd("check", *map(str, sorted(EXAMPLES.glob("*.xml"))), str(REPO / "tests/data/seeds/fig7_2.xml"))
    assert result.returncode == 0
    header = result.stdout.splitlines()[0].split()
    arms: dict[str, list[str]] = {}
    for robot, arm in variants():  # one column per installed robot, or per arm of a two-arm one
        arms.setdefault(robot, []).append(arm)
    columns = [f"{robot}:{arm}" if len(names) > 1 else robot for robot, names in arms.items() for arm in names]
    assert header == ["task", *columns]
    assert [c for c in columns if c.split(":")[0] in BUILTIN] == [
        "baxter:right", "baxter:left", "melfa", "tombatossals:right", "tombatossals:left"]
    assert any(line.startswith(str(EXAMPLES / "pick_and_place.xml")) and line.count("yes") == len(columns)
               for line in result.stdout.splitlines())
    assert "why not:" in result.stdout and "fig7_2.xml:14:3: error[TRN001]" in result.stdout


def test_check_as_json_gives_each_task_and_robot_its_verdict_and_reasons(tmp_path):
    broken = tmp_path / "broken.xml"
    broken.write_text("<statemachine>")
    seeds = REPO / "tests/data/seeds/fig7_2.xml"
    result = atd("check", str(EXAMPLES / "pick_and_place.xml"), str(seeds), str(broken), "--format", "json")
    assert result.returncode == 1  # one task is not a valid ATD, as in text
    found = json.loads(result.stdout)
    pick, fig, bad = found["tasks"]
    assert "melfa" in found["robots"] and set(pick["robots"]) == set(found["robots"])
    assert pick["valid"] and all(v["translatable"] and not v["errors"] for v in pick["robots"].values())
    assert any(not v["translatable"] and any("fig7_2.xml:14:3: error[TRN001]" in e for e in v["errors"])
               for v in fig["robots"].values())
    assert not bad["valid"] and "error[ATD003]" in bad["errors"][0] and bad["robots"] == {}


def test_robots_as_json_list_every_robot_and_show_its_sheet():
    listed = json.loads(atd("robots", "--format", "json").stdout)
    assert json.loads(atd("robots", "list", "--format", "json").stdout) == listed
    melfa = next(r for r in listed if r["name"] == "melfa")
    assert melfa["arms"] == ["main"] and "grasp" in melfa["primitives"] and "grasp_stable" in melfa["events"]
    sheet = json.loads(atd("robots", "show", "melfa", "--format", "json").stdout)
    assert sheet["arm"] == "main" and sheet["config"]["controllers"]["squeeze"]["grasp_force"] == 15.0
    assert {"abstract", "concrete", "extra_parameters", "control_and_sensors"} <= set(sheet["primitives"][0])
    assert any(e["event"] == "grasp_stable" and "tactile_force_above" in e["detected_by"] for e in sheet["events"])
    misplaced = atd("robots", "--format", "json", "show", "melfa")
    assert misplaced.returncode == 2 and misplaced.stderr.strip() == (
        "error: give --format after the sub-command: atd robots show ... --format json")


def test_robots_list_and_show():
    listing = atd("robots", "list").stdout
    assert "melfa: Mitsubishi Melfa RV-3SB" in listing and "tombatossals:" in listing and "baxter:" in listing
    assert atd("robots").stdout == listing  # bare `atd robots` lists too
    show = atd("robots", "show", "melfa").stdout
    assert "| slide | - | - | - |" in show
    assert "success (leaving place)" not in show  # a place succeeds as any move does: where it was going


def test_a_separately_installed_package_adds_a_robot(tmp_path):
    """Another distribution, laid out as pip installs a wheel (package + .dist-info with an
    `atd.factories` entry point) in its own site dir: found by real entry-point discovery.
    (Building it with pip needs setuptools >= 68 and wheel, which this offline machine lacks.)"""
    site = tmp_path / "site"
    write_robot_package(site, "toyrobot")
    env = {**os.environ, "PYTHONPATH": f"{REPO}{os.pathsep}{site}"}
    assert "toyrobot: a Melfa twin from another package" in atd("robots", "list", env=env).stdout
    out = tmp_path / "toy.xml"
    assert atd("translate", str(EXAMPLES / "simple_move.xml"), "-r", "toyrobot", "-o", str(out), env=env).returncode == 0
    assert read_estd(out)[0].robot == "toyrobot"
    assert "toyrobot" not in atd("robots", "list").stdout
