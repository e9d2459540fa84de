"""Issue 12: every number a user gives is checked against one declared range; NaN and
infinities never pass, and the refusal names the place and the allowed range."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
from click.testing import CliRunner

from atd.cli import main
from atd.model import load_task
from atd.model.controllers import CONTROLLERS, parse_value
from atd.model.ranges import Range
from factories.config import ConfigError, load_config

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "simple_move.xml"


def with_moving_state_text(tmp_path: Path, extra: str) -> Path:
    path = tmp_path / "t.xml"
    path.write_text(EXAMPLE.read_text().replace('<state name="moving" type="move">',
                                                f'<state name="moving" type="move">{extra}'))
    return path


@pytest.mark.parametrize("value", ["0", "nan", "-1", "inf", "1e9"])
def test_a_speed_limit_that_would_be_no_limit_is_refused_at_its_line(tmp_path: Path, value: str) -> None:
    task = with_moving_state_text(tmp_path, f'<parameter name="max_speed">{value}</parameter>')
    _, found = load_task(task)
    assert [(d.code, d.loc.line) for d in found] == [("ATD108", 16)]
    assert "(0, 2] m/s" in found[0].message


MINIMAL = """<statemachine>
  <object>{element}</object>
  <state name="reach" type="move"><path><position>0.1 0 0.15</position></path></state>
  <state name="done" type="success"/>
  <transition origin="reach" destination="done"><timeout>{seconds}</timeout></transition>
</statemachine>"""


@pytest.mark.parametrize("element, allowed", [
    ("<weight>1e-12</weight>", "[0.001, 50] kg"),
    ("<weight>NaN</weight>", "[0.001, 50] kg"),
    ("<friction>-0.5</friction>", "[0, 10]"),
    ("<size>0.05 0.05 inf</size>", "[0.001, 10] m"),
    ("<size>0.05 1e-9 0.05</size>", "[0.001, 10] m"),  # MuJoCo refused the model: a traceback from atd run
])
def test_object_values_outside_what_the_engines_simulate_are_refused(tmp_path: Path, element: str,
                                                                       allowed: str) -> None:
    task = tmp_path / "t.xml"
    task.write_text(MINIMAL.format(element=element, seconds=5))
    _, found = load_task(task)
    assert [(d.code in ("ATD106", "ATD108"), d.loc.line, d.loc.col) for d in found] == [(True, 2, 11)]
    assert allowed in found[0].message


@pytest.mark.parametrize("seconds", ["nan", "0", "-3", "1e300"])
def test_timeouts_are_finite_and_positive(tmp_path: Path, seconds: str) -> None:
    task = tmp_path / "t.xml"
    task.write_text(MINIMAL.format(element="", seconds=seconds))
    _, found = load_task(task)
    timeout = next(d for d in found if d.loc.line == 5)
    assert (timeout.code in ("ATD106", "ATD108"), timeout.loc.col) == (True, 49)
    assert "timeout" in timeout.message and "(0, 86400] s" in timeout.message


def test_a_config_file_nan_names_the_file_line_table_and_range(tmp_path: Path) -> None:
    config = tmp_path / "c.toml"
    config.write_text("# a user's tuning\n[melfa.conditions.grasp_stable.tactile_force_above]\nforce_threshold = nan\n")
    with pytest.raises(ConfigError, match=r"c\.toml:3:1: \[melfa\.conditions\.grasp_stable\.tactile_force_above\] "
                                          r"force_threshold: nan is not a finite number; give one in \(0, 1000\] N"):
        load_config(config, "melfa")


@pytest.mark.parametrize("option, value, said", [("--budget", "nan", "not a finite number"),
                                                  ("--budget", "0", "outside (0, 86400] s"),
                                                  ("--seed", "-1", "outside [0, 4294967295]"),
                                                  ("--seed", "2.5", "not an integer"),
                                                  ("--seed", "4294967296", "4294967296 is outside"),
                                                  ("--seed", "9" * 400, "9999999999... (400 digits) is outside")])
def test_command_line_numbers_are_checked_before_anything_runs(option: str, value: str, said: str) -> None:
    result = CliRunner().invoke(main, ["run", str(EXAMPLE), "--robot", "melfa", option, value])
    assert result.exit_code == 2 and said in result.output and "Traceback" not in result.output


@pytest.mark.parametrize("table, line, said", [
    ("conditions.grasp_stable.tactile_force_above", "min_pads = " + "9" * 400, "(400 digits) is outside [1, 64]"),
    ("controllers.close_until_force", "grasp_force = " + "9" * 400, "(400 digits) is outside (0, 1000] N"),
    ("conditions.grasp_stable.tactile_force_above", "min_pads = 2.5", "2.5 is not an integer"),
    ("controllers.cartesian_move", "velocity_limits = [true, 0, 0, 0, 0, 0]", "True is not a number"),
])
def test_config_values_no_float_can_hold_or_that_are_no_numbers_are_refused(tmp_path: Path, table: str, line: str,
                                                                            said: str) -> None:
    config = tmp_path / "c.toml"
    config.write_text(f"[melfa.{table}]\n{line}\n")
    with pytest.raises(ConfigError, match=re.escape(said)):
        load_config(config, "melfa")


def test_vectors_and_points_are_checked_number_by_number() -> None:
    specs = CONTROLLERS["cartesian_move"].params
    with pytest.raises(ValueError, match="nan is not a finite number"):
        parse_value(specs["waypoints"], "0 0 0; 0 nan 0")
    with pytest.raises(ValueError, match="outside"):
        parse_value(specs["velocity_limits"], "0 0 0 0 0 -1")


def test_every_numeric_parameter_has_a_range_its_default_lies_in() -> None:
    for controller in CONTROLLERS.values():
        for name, spec in controller.params.items():
            assert isinstance(spec.allowed, Range)
            if isinstance(spec.default, float):
                assert spec.allowed.problem(spec.default) is None, (controller.name, name)


def test_every_default_of_the_vocabulary_lies_in_its_declared_range() -> None:
    # A parameter added without a range (a count read as a fraction, a weight in kg with
    # no range for kg) makes every ESTD that uses it untranslatable.
    from atd.model.controllers import CONDITIONS, CONTROLLERS, ParamType

    outside = []
    for table in (CONTROLLERS, CONDITIONS):
        for name, spec in table.items():
            for param, p in spec.params.items():
                if p.default is None or p.type in (ParamType.WORD, ParamType.FLAG, ParamType.POINTS):
                    continue
                values = p.default if isinstance(p.default, tuple) else (p.default,)
                outside += [f"{name}.{param} = {v}: {p.allowed.problem(float(v))}"
                            for v in values if p.allowed.problem(float(v))]
    assert outside == []


@pytest.mark.parametrize("word", ["1_0", "١٢", "0x10"])
def test_numbers_only_python_reads_are_refused_everywhere_a_number_is_read(tmp_path: Path, word: str) -> None:
    """float() takes '1_0' as 10 and Arabic-Indic digits as ours; no schema, TOML or other tool does."""
    task = with_moving_state_text(tmp_path, f'<parameter name="force_threshold">{word}</parameter>'
                                            f'<hand_opening>{word}</hand_opening>')
    _, found = load_task(task)
    assert {d.code for d in found} == {"ATD106", "ATD108"}
    assert all(f"'{word}' is not a number" in d.message for d in found)
    for option in (["--seed", word], ["--budget", word]):
        result = CliRunner().invoke(main, ["run", str(EXAMPLE), "--robot", "melfa", *option])
        assert result.exit_code == 2 and f"'{word}' is not" in result.output


def test_the_plain_forms_of_a_number_are_read() -> None:
    spec = CONTROLLERS["cartesian_move"].params["max_speed"]
    assert [parse_value(spec, text) for text in ("1", "+.5", "2.", "1E-1", " 0.25 ")] == [1.0, 0.5, 2.0, 0.1, 0.25]


@pytest.mark.parametrize("field, value, said", [
    ('"weight": 0.1', '"weight": NaN', "'nan' is not a valid value"),
    ('"weight": 0.1', '"weight": ' + "9" * 400, "'inf' is not a valid value"),
    ('"matrix": [1.0', '"matrix": [Infinity', "'inf' is not a valid value"),
    ('"size": [0.05', '"size": [-0.05', "-0.05 is outside [0.001, 10] m"),
    ('"initial": "reach"', '"initial": "re\\u0000ach"', "no NULL bytes"),
    ('"weight": 0.1', '"weight": true', "should be a valid number"),
    ('"weight": 0.1', '"weight": "0.1"', "should be a valid number"),
])
def test_an_estd_in_json_is_checked_as_its_xml_form_is(field: str, value: str, said: str) -> None:
    """A NaN weight in a JSON ESTD crashed MuJoCo's model compiler; an infinite pose ran to the watchdog."""
    from atd.model.estd_xml import estd_to_json, parse_estd_json
    from factories.registry import create
    from translator import translate

    task, _ = load_task(EXAMPLE.parents[1] / "tests" / "data" / "known_box" / "pick_one.xml")
    text = json.dumps(json.loads(estd_to_json(translate(task, create("melfa")).estd)))
    assert parse_estd_json(text.encode(), "e.json")[1] == []
    assert field in text
    estd, found = parse_estd_json(text.replace(field, value, 1).encode(), "e.json")
    assert estd is None and found and said in found[0].message, found
    assert str(found[0].loc) == "e.json"
