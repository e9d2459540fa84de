"""Issue 12: `atd run` simulates in a child process, so a crash in an engine's C code is a
one-line error naming the engine and the signal (exit 5) with no output written, and
Ctrl-C or SIGTERM still stop the whole run at once."""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from atd.runtime.isolated import in_child
from atd.runtime.session import Unrunnable
from tests.conftest import EXAMPLES

# An engine function replaced by a crash, as its C code would have one: stepping, and
# loading the robot (where a mesh is read).
CRASHES = {"mujoco-step": ("mujoco", "import mujoco as engine; engine.mj_step = crash", signal.SIGSEGV),
           "pybullet-step": ("pybullet", "import pybullet as engine; engine.stepSimulation = crash", signal.SIGABRT),
           "pybullet-load": ("pybullet", "import pybullet as engine; engine.loadURDF = crash", signal.SIGSEGV)}


def _atd_with(patch: str, signum: int) -> str:
    return (f"import os\ndef crash(*args, **kwargs):\n    os.kill(os.getpid(), {signum})\n{patch}\n"
            "from atd.cli import main\nmain()")


@pytest.fixture
def folder(tmp_path: Path) -> Path:
    shutil.copy(EXAMPLES / "simple_move.xml", tmp_path / "move.xml")
    return tmp_path


@pytest.mark.parametrize("crash", CRASHES)
def test_a_crash_in_the_engine_is_one_line_exit_5_and_nothing_written(folder: Path, crash: str) -> None:
    engine, patch, signum = CRASHES[crash]
    done = subprocess.run([sys.executable, "-c", _atd_with(patch, signum), "run", "move.xml", "--robot",
                           "melfa", "--engine", engine, "-q", "--trace", "t.jsonl", "--record", "r.mcap"],
                          cwd=folder, capture_output=True, text=True, timeout=300)
    assert done.returncode == 5, done.stderr[-2000:]
    name = signal.Signals(signum).name
    assert done.stderr.splitlines()[-1] == (f"error: the {engine} engine crashed (killed by {name}) running move.xml; "
                                            f"try --engine {'pybullet' if engine == 'mujoco' else 'mujoco'}")
    assert "Traceback" not in done.stderr and done.stdout == ""
    assert sorted(p.name for p in folder.iterdir()) == ["move.xml"]


def _started_run(folder: Path) -> subprocess.Popen:
    """`atd run` in real time in a session of its own (as a terminal's foreground job), once it
    has begun to simulate. Its SIGINT is restored as a terminal would have it: a test suite
    started in the background (`cmd &`) ignores SIGINT, and so would the run, rightly."""
    process = subprocess.Popen([sys.executable, "-m", "atd", "run", str(EXAMPLES / "pick_and_place.xml"),
                                "--robot", "melfa", "--realtime", "--trace", "t.jsonl"],
                               cwd=folder, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                               start_new_session=True,
                               preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    assert process.stderr is not None
    first = process.stderr.readline()  # the first progress line: the child is simulating
    assert "real time]" in first, first
    return process


def _gone(group: int) -> bool:
    """No process of the run's group is left (the child did not outlive the parent)."""
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline:
        try:
            os.killpg(group, 0)
        except ProcessLookupError:
            return True
        time.sleep(0.1)
    return False


@pytest.mark.parametrize("to_group", [True, False], ids=["ctrl-c-on-a-terminal", "sigint-to-atd"])
def test_ctrl_c_stops_the_run_with_aborted_and_leaves_nothing(tmp_path: Path, to_group: bool) -> None:
    process = _started_run(tmp_path)
    (os.killpg if to_group else os.kill)(process.pid, signal.SIGINT)
    out, err = process.communicate(timeout=60)
    assert process.returncode == 1, err
    assert err.strip().splitlines()[-1] == "Aborted!" and "Traceback" not in err
    assert _gone(process.pid)
    assert list(tmp_path.iterdir()) == []


def test_sigterm_ends_the_run_and_its_engine(tmp_path: Path) -> None:
    process = _started_run(tmp_path)
    process.terminate()
    process.communicate(timeout=60)
    assert process.returncode == -signal.SIGTERM
    assert _gone(process.pid)
    assert list(tmp_path.iterdir()) == []


def test_a_runs_refusal_reaches_the_command_with_its_words() -> None:
    """Refusals raised where the engine runs (exit 4, 1, 2 in `atd run`) arrive whole."""
    def refuse() -> None:
        raise Unrunnable(["no tactile pads", "no wrist sensor"])

    with pytest.raises(Unrunnable) as refused:
        in_child(refuse)
    assert refused.value.problems == ["no tactile pads", "no wrist sensor"]
    assert str(refused.value) == "this ESTD does not fit the robot:\n  no tactile pads\n  no wrist sensor"
    assert in_child(lambda: {"answer": 42}) == {"answer": 42}
