"""What `atd run` prints around the outcome: a progress line that leaves nothing garbled on a
terminal, the summary on lines of its own, one line of what to try next, and `--format json`."""

from __future__ import annotations

import json
import os
import pty
import re
import subprocess
import sys

from tests.runtime.test_run_cli import PICK_AND_PLACE

STATES = ["approach", "descend", "grasp", "lift", "carry", "put_down", "let_go", "retreat", "done"]
# Each state's line, written over the line updated in place during the state before it
# (grasp then lift, put_down then let_go: shorter names over longer ones).
PROGRESS = re.compile(rf"\[ *\d+\.\d\d s +\d+\.\dx real time\]  ({'|'.join(STATES)})")


def _screen(output: str) -> list[str]:
    """The lines a terminal shows after `output`: carriage return, erase to end of line, newline."""
    lines, col = [""], 0
    for token in re.findall(r"\x1b\[K|\r|\n|[^\x1b\r\n]+", output):
        line = lines[-1]
        if token == "\r":
            col = 0
        elif token == "\n":
            lines.append("")
            col = 0
        elif token == "\x1b[K":
            lines[-1] = line[:col]
        else:
            lines[-1] = line[:col] + token + line[col + len(token):]
            col += len(token)
    return lines


def _on_a_terminal(*args: str) -> str:
    """stdout and stderr of `atd ARGS` on one pseudo-terminal, as a user sees them."""
    leader, follower = pty.openpty()
    done = subprocess.run([sys.executable, "-m", "atd", *args], stdout=follower, stderr=follower, timeout=300)
    os.close(follower)
    chunks = []
    while True:
        try:
            chunk = os.read(leader, 65536)
        except OSError:  # EIO: the terminal's other end is closed and everything was read
            break
        if not chunk:
            break
        chunks.append(chunk)
    os.close(leader)
    assert done.returncode == 0, b"".join(chunks).decode()
    return b"".join(chunks).decode()


def test_on_a_terminal_the_progress_line_leaves_nothing_behind_and_the_summary_starts_its_own_line():
    output = _on_a_terminal("run", PICK_AND_PLACE, "--robot", "melfa")
    assert output.count("]  grasp") > 1  # the grasp's line was updated in place
    screen = _screen(output.replace("\r\n", "\n"))
    progress = [line for line in screen if line.startswith("[")]
    assert [m[1] if (m := PROGRESS.fullmatch(line)) else line for line in progress] == STATES[:-1]
    assert "pick_and_place.xml on melfa (main arm) in mujoco, seed 0" in screen
    assert screen[-2] == (f"next: atd run {PICK_AND_PLACE} --robot melfa --record run.mcap, then atd report run.mcap "
                          "(the task graph, timeline and signals)")


def test_json_gives_the_outcome_its_path_and_events(tmp_path):
    trace = tmp_path / "run.jsonl"
    result = subprocess.run([sys.executable, "-m", "atd", "run", PICK_AND_PLACE, "--robot", "melfa", "--format", "json",
                             "-q", "--trace", str(trace)], capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    run = json.loads(result.stdout)
    assert run["succeeded"] is True and run["end_state"] == "done" and run["summary"] == "succeeded: reached 'done'"
    assert (run["robot"], run["arm"], run["engine"], run["seed"]) == ("melfa", "main", "mujoco", 0)
    assert [v["state"] for v in run["path"]] == STATES
    assert run["path"][2]["left_on"] == ["success", "grasp_stable"] and run["path"][-1]["left"] is None
    assert 10 < run["sim_time"] < 30 and run["path"][-1]["entered"] <= run["sim_time"]
    stable = next(e for e in run["events"] if e["atd"] == "grasp->lift/grasp_stable")
    assert stable["conditions"][0]["kind"] == "tactile_force_above" and stable["t"] == run["path"][3]["entered"]
    x, y, _ = next(iter(run["objects"].values()))
    assert abs(x - 0.10) < 0.02 and abs(y - 0.10) < 0.02
    assert run["outputs"] == {"trace": str(trace), "record": None, "video": None}
    traced = [json.loads(line) for line in trace.read_text().splitlines()]
    assert len(run["events"]) == sum(r["type"] == "event" for r in traced)  # every event, none left out
