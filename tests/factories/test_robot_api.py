"""`atd.robot_api` is the one documented place a factory author imports from."""

from __future__ import annotations

import ast
import dataclasses
import inspect
import textwrap
from dataclasses import replace

import pytest

import atd.robot_api as api
import factories.base
import factories.description
from factories.melfa.description import description as melfa


def test_it_re_exports_the_very_objects_existing_imports_use():
    assert api.Factory is factories.base.Factory and api.Hand is factories.base.Hand
    assert api.HandModel is factories.description.Hand and api.RobotDescription is factories.description.RobotDescription
    assert all(hasattr(api, name) for name in api.__all__)


def _undocumented_fields(cls: type) -> list[str]:
    body = ast.parse(textwrap.dedent(inspect.getsource(cls))).body[0].body
    documented = {stmt.target.id for stmt, after in zip(body, body[1:])
                  if isinstance(stmt, ast.AnnAssign) and isinstance(after, ast.Expr)
                  and isinstance(after.value, ast.Constant) and isinstance(after.value.value, str)}
    return [f.name for f in dataclasses.fields(cls) if f.name not in documented]


@pytest.mark.parametrize("name", [n for n in api.__all__ if dataclasses.is_dataclass(getattr(api, n))])
def test_every_field_of_every_exported_type_has_a_docstring(name):
    assert _undocumented_fields(getattr(api, name)) == []


def test_every_exported_class_and_function_says_what_it_is_for():
    missing = [n for n in api.__all__ if (inspect.isclass(getattr(api, n)) or inspect.isfunction(getattr(api, n)))
               and not inspect.getdoc(getattr(api, n))]
    assert missing == []


def test_a_home_is_found_from_the_description_and_an_unreachable_one_is_explained():
    robot = melfa()
    found = api.with_home(replace(robot, home=(0.0,) * 6), (0.0, 0.3, 0.9, 0.0, 0.4, 0.0))
    assert found.home == pytest.approx(robot.home, abs=2e-3)
    far = replace(robot, base=api.Origin((-3.0, 0.0, 0.0)))
    with pytest.raises(ValueError, match="robot .melfa.: no home found .* move `base` closer to the work area"):
        api.with_home(far, robot.home)
