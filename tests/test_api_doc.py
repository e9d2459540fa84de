"""docs/api.md's examples run as written, in order, and do what the page says."""

from __future__ import annotations

import contextlib
import io
import os
import re
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]


def test_the_api_page_runs_as_written() -> None:
    blocks = re.findall(r"```python\n(.*?)```", (REPO / "docs" / "api.md").read_text(), re.S)
    scope: dict = {}
    printed = io.StringIO()
    here = Path.cwd()
    os.chdir(REPO)
    try:
        with contextlib.redirect_stdout(printed):
            for block in blocks:
                exec(compile(block, "docs/api.md", "exec"), scope)
    finally:
        os.chdir(here)
    assert scope["problems"] == [] and scope["result"].succeeded
    assert scope["result"].path[0] == "approach" and "object" in scope["result"].object_positions
    assert "examples/no_such_task.xml" in printed.getvalue()
    assert scope["two"].roles == {"holder": "left", "worker": "right"}
    assert len(scope["records"]) == 2 and all(r.cell.robot == "melfa" for r in scope["records"])


def test_the_api_is_loaded_on_first_use_and_says_what_is_wrong() -> None:
    """Even where a subpackage of the same first name was imported before it (atd.campaign)."""
    import subprocess
    import sys

    loaded = subprocess.run([sys.executable, "-c", "import atd, sys, atd.campaign.spec; print('atd.api' in sys.modules); "
                             "print(callable(atd.run) and callable(atd.run_campaign), 'atd.api' in sys.modules)"], capture_output=True, text=True, check=True)
    assert loaded.stdout.split() == ["False", "True", "True"]
    import atd

    with pytest.raises(atd.AtdError, match="robot='melfa'"):
        atd.run("examples/pick_and_place.xml")
