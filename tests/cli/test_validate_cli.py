"""`atd validate` as a user meets it: the real console script, its output and exit codes."""

import json
import subprocess
import sys

from tests.conftest import EXAMPLES, SEEDS


def atd(*args: str, cwd=None) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "atd", *args], capture_output=True, text=True, cwd=cwd, timeout=60)


def test_examples_validate_with_exit_zero():
    result = atd("validate", *map(str, sorted(EXAMPLES.glob("*.xml"))))
    assert result.returncode == 0
    assert result.stdout.strip().endswith("files checked: 0 errors, 0 warnings")


def test_warnings_keep_exit_zero():
    result = atd("validate", str(SEEDS / "fig7_2.xml"))
    assert result.returncode == 0
    assert "fig7_2.xml:2:3: warning[ATD210]" in result.stdout


def test_errors_give_exit_one_with_compiler_style_lines(atd_file):
    path = atd_file('<statemachine>\n  <state name="a" type="mvoe"/>\n</statemachine>\n')
    result = atd("validate", str(path))
    assert result.returncode == 1
    assert f"{path}:2:3: error[ATD104]: 'mvoe' is not a state type" in result.stdout
    assert "hint: did you mean 'move'?" in result.stdout
    assert "Traceback" not in result.stdout + result.stderr


def test_a_value_read_before_it_is_written_is_one_located_error(atd_file):
    """Issue 31: perceive writes the approach only when it found an object."""
    path = atd_file("""\
        <statemachine>
          <environment><container name="box"><pose>1 0 0 0.3  0 1 0 0  0 0 1 0  0 0 0 1</pose>
            <size>0.3 0.25 0.1</size></container></environment>
          <state name="look" type="perceive" container="box"><method>random_blind</method>
            <writes name="approach" kind="pose"/></state>
          <state name="reach" type="move"><target from="approch"/></state>
          <state name="done" type="success"/>
          <transition origin="look" destination="reach"><object_found/></transition>
          <transition origin="look" destination="done"><nothing_found/></transition>
          <transition origin="reach" destination="done"><success/></transition>
        </statemachine>
        """)
    result = atd("validate", str(path))
    assert result.returncode == 1 and "Traceback" not in result.stdout + result.stderr
    assert result.stdout.splitlines()[:2] == [
        f"{path}:6:3: error[ATD221]: state 'reach' reads 'approch', which is not written on every way to it: "
        "look -> reach writes it nowhere", "  hint: did you mean 'approach'?"]


def test_hostile_input_gives_a_diagnostic_not_a_traceback(tmp_path):
    path = tmp_path / "x.xml"
    path.write_bytes(b"\x89PNG\r\n\x1a\n\x00\x00binary")
    result = atd("validate", str(path))
    assert result.returncode == 1
    assert "error[ATD006]" in result.stdout and "Traceback" not in result.stderr


def test_json_format_for_tools(atd_file):
    bad = atd_file('<statemachine><state name="a" type="success"/>'
                   '<transition origin="a" destination="b"><success/></transition></statemachine>')
    result = atd("validate", "--format", "json", str(bad), str(EXAMPLES / "pick_and_place.xml"))
    report = json.loads(result.stdout)
    assert result.returncode == 1
    assert [f["valid"] for f in report["files"]] == [False, True]
    codes = {d["code"] for d in report["files"][0]["diagnostics"]}
    assert {"ATD202", "ATD205"} <= codes
    assert report["files"][0]["diagnostics"][0]["loc"]["line"] == 1


def test_usage_error_gives_exit_two():
    assert atd("validate").returncode == 2
    assert atd("validate", "--format", "yaml", "x.xml").returncode == 2
