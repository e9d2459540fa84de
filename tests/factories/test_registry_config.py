"""The registry agrees with pyproject.toml; config files are checked and layered."""

from __future__ import annotations

import tomllib

import pytest

from factories.config import ConfigError, load_config
from factories.registry import BUILTIN, create
from tests.conftest import REPO


def test_builtin_robots_are_the_entry_points_pyproject_declares():
    project = tomllib.loads((REPO / "pyproject.toml").read_text())
    assert project["project"]["entry-points"]["atd.factories"] == BUILTIN


def test_shipped_configs_load_and_user_config_wins(tmp_path):
    user = tmp_path / "c.toml"
    user.write_text("[baxter.controllers.place]\nforce_threshold = 12\n[melfa.controllers.place]\nvelocity = 0.01\n")
    factory = create("baxter", config=user)
    assert factory.config.controllers["place"] == {"force_threshold": 12.0, "carry_threshold": 30.0, "weigh_time": 0.0, "filter_time": 0.05}


@pytest.mark.parametrize("text, message", [
    ("[melfa.controllers.warp]\nspeed = 1\n", "[melfa.controllers.warp] names no controller"),
    ("[melfa.controllers.place]\nvelocity = 'fast'\n", "[melfa.controllers.place] velocity: 'fast' is not a number"),
    ("[melfa.conditions.grasp_stabel.timeout]\nseconds = 1\n", "[melfa.conditions.grasp_stabel] names no abstract event"),
    ("[melfa.conditions.timeout.timeout]\nseconds = 1\n", "'seconds' comes from the task"),
    ("[melfa.robot]\nx = 1\n", "[melfa.robot] is not a section"),
    ("[melfa\n", "not valid TOML"),
    ("[melfa]\ncontrollers = 3\n", ":2:1: [melfa.controllers] must be a table, not 3"),
    ("melfa = 3\n", ":1:1: [melfa] must be a table"),
    ("[melfa.conditions]\ngrasp_stable = 3\n", ":2:1: [melfa.conditions.grasp_stable] must be a table"),
    ("[melfa.controllers.place]\n\nvelocity = -1\n", ":3:1: [melfa.controllers.place] velocity: -1 is outside"),
])
def test_bad_config_files_name_the_file_the_line_the_table_and_the_fix(tmp_path, text, message):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(ConfigError, match=None) as info:
        load_config(path, "melfa")
    assert str(info.value).startswith(str(path)) and message in str(info.value)
