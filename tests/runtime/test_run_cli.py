"""`atd run` as a user meets it: the real command, its summary, trace and exit codes."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys

import pytest

from tests.conftest import EXAMPLES, KNOWN_BOX

PICK_AND_PLACE = str(EXAMPLES / "pick_and_place.xml")
SHORT_MOVE = """
    <statemachine>
      <state name="reach" type="move"><path><position>0.10 0.0 0.20</position></path></state>
      <state name="done" type="success"/>
      <transition origin="reach" destination="done"><success/></transition>
    </statemachine>"""  # a run of about 2 s, for what records it


def atd(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "atd", *args], capture_output=True, text=True, timeout=300)


def test_the_flagship_demo_succeeds_and_reports_in_task_terms():
    result = atd("run", PICK_AND_PLACE, "--robot", "melfa")
    assert result.returncode == 0, result.stdout + result.stderr
    out = result.stdout
    assert "outcome: succeeded: reached 'done'" in out
    assert "left on success & grasp_stable (grasp->lift)" in out
    assert "grasp->lift/grasp_stable: tactile_force_above(" in out
    rests = next(line for line in out.splitlines() if line.startswith("the object rests at"))
    x, y, z = (float(v) for v in rests.split("(")[1].rstrip(")").split(","))
    assert ((x - 0.10) ** 2 + (y - 0.10) ** 2) ** 0.5 < 0.02 and abs(z - 0.025) < 0.005
    assert "[" in result.stderr and "approach" in result.stderr  # live progress, one line per state


def test_same_seed_same_trace_and_every_record_traces_back_to_the_atd(tmp_path):
    traces = []
    for name in ("a.jsonl", "b.jsonl"):
        path = tmp_path / name
        assert atd("run", PICK_AND_PLACE, "--robot", "melfa", "--seed", "3", "--trace", str(path), "-q").returncode == 0
        traces.append(path.read_bytes())
    assert traces[0] == traces[1]
    records = [json.loads(line) for line in traces[0].splitlines()]
    states = {"approach", "descend", "grasp", "lift", "carry", "put_down", "let_go", "retreat", "done"}
    assert {r["atd"] for r in records if r["type"] in ("enter", "exit", "end")} == states
    events = [r for r in records if r["type"] == "event"]
    assert all(r["atd"].startswith(r["transition"] + "/") for r in events)
    assert all(c["atd"] == r["atd"] for r in events for c in r["conditions"])
    assert records[-1]["type"] == "end" and records[-1]["outcome"] == "success"
    assert not list(tmp_path.glob(".*partial"))  # the trace was moved into place whole


def test_an_estd_file_runs_as_is(tmp_path):
    estd = tmp_path / "pp.estd.xml"
    assert atd("translate", PICK_AND_PLACE, "--robot", "melfa", "-o", str(estd), "-q").returncode == 0
    assert atd("run", str(estd), "-q").returncode == 0
    wrong = atd("run", str(estd), "--robot", "baxter", "-q")
    assert wrong.returncode == 2 and "was translated for 'melfa', not 'baxter'" in wrong.stderr


def test_the_watchdog_ends_a_run_that_outlives_its_budget():
    result = atd("run", PICK_AND_PLACE, "--robot", "melfa", "--budget", "1", "-q")
    assert result.returncode == 3
    assert "outcome: failed: the watchdog stopped the run in 'descend' after 1 s of simulated time" in result.stdout


def test_a_task_the_robot_cannot_do_exits_4_with_the_reason(atd_file):
    path = atd_file("""
        <statemachine>
          <state name="wipe" type="slide"><path><position>0.1 0.1 0.02</position></path></state>
          <state name="done" type="success"/>
          <transition origin="wipe" destination="done"><success/></transition>
        </statemachine>""")
    result = atd("run", str(path), "--robot", "melfa", "-q")
    assert result.returncode == 4
    assert "the Melfa has no slide primitive" in result.stderr and "Traceback" not in result.stderr


def test_bad_input_gives_a_diagnostic_not_a_traceback(atd_file):
    broken = atd_file("<statemachine><state name='a' type='move'/>")
    result = atd("run", str(broken), "--robot", "melfa")
    assert result.returncode == 1 and "error[ATD003]" in result.stderr and "Traceback" not in result.stderr
    without_robot = atd("run", str(broken))  # a broken file is reported as broken, whatever else is missing
    assert without_robot.returncode == 1 and "error[ATD003]" in without_robot.stderr
    budget = atd("run", PICK_AND_PLACE, "--robot", "melfa", "--budget", "-1")
    assert budget.returncode == 2 and "'--budget'" in budget.stderr
    no_robot = atd("run", PICK_AND_PLACE)
    assert no_robot.returncode == 2 and "--robot" in no_robot.stderr
    unknown = atd("run", PICK_AND_PLACE, "--robot", "r2d2")
    assert unknown.returncode == 2 and "no robot 'r2d2' is installed" in unknown.stderr


def test_video_as_mp4_is_a_playable_h264_file(tmp_path, atd_file):
    import imageio_ffmpeg

    path = atd_file(SHORT_MOVE)
    mp4 = tmp_path / "run.mp4"
    result = atd("run", str(path), "--robot", "melfa", "--video", str(mp4), "-q")
    assert result.returncode == 0, result.stderr
    frames, seconds = imageio_ffmpeg.count_frames_and_secs(str(mp4))
    assert f"video: {mp4} ({frames} frames, 640x480, workspace camera)" in result.stdout and frames >= 3
    assert abs(seconds - frames * 0.1) < 0.15  # one frame per 0.1 s of simulated time
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.mp4", "task.xml"]  # no temporary file left


def test_an_mp4_without_ffmpeg_is_refused_before_the_run(tmp_path, monkeypatch):
    from atd.sim import video

    monkeypatch.setattr(video, "mp4_encoder", lambda: None)
    with pytest.raises(video.VideoError, match=r"MP4 needs ffmpeg.*pip install 'atd-robotics\[video\]', or name the file \*\.gif"):
        video.check_video_path(tmp_path / "run.mp4")


def test_video_and_viewer_refusals_are_clear(tmp_path, monkeypatch):
    avi = atd("run", PICK_AND_PLACE, "--robot", "melfa", "--video", str(tmp_path / "run.avi"), "-q")
    assert avi.returncode == 2 and "name the file *.gif or *.mp4" in avi.stderr and not (tmp_path / "run.avi").exists()
    nowhere = atd("run", PICK_AND_PLACE, "--robot", "melfa", "--video", str(tmp_path / "no" / "run.gif"), "-q")
    assert nowhere.returncode == 2 and "does not exist" in nowhere.stderr
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    for engine in ("mujoco", "pybullet"):
        viewer = atd("run", PICK_AND_PLACE, "--robot", "melfa", "--engine", engine, "--viewer", "-q")
        assert viewer.returncode == 2 and "--viewer needs a display" in viewer.stderr, engine


def test_empty_the_box_loops_over_its_sub_task_until_nothing_is_left(tmp_path):
    """Thesis 3.4.3: pick-and-place rounds as a sub-task; the round that finds nothing ends the loop."""
    trace = tmp_path / "t.jsonl"
    result = atd("run", str(KNOWN_BOX / "empty_the_box.xml"), "--robot", "melfa", "--trace", str(trace), "-q")
    assert result.returncode == 0, result.stdout
    assert "outcome: succeeded: reached 'box_empty'" in result.stdout
    records = [json.loads(line) for line in trace.read_text().splitlines()]
    rounds = [r for r in records if r["type"] == "enter" and r["state"] == "pick_one"]
    ends = [r["state"] for r in records if r["type"] == "end"]
    assert len(rounds) == 2 and ends == ["pick_one/placed", "pick_one/nothing_there", "box_empty"]
    # The empty box is the grasp's own verdict, not a timeout standing in for it.
    verdict = [r for r in records if r["type"] == "event" and r["atd"].endswith("grasp->nothing_there/error")]
    assert len(verdict) == 1 and "the jaws closed on nothing" in json.dumps(verdict[0])
    rests = next(line for line in result.stdout.splitlines() if line.startswith("the object rests at"))
    y = float(rests.split(",")[1])
    assert y > 0.05  # outside the box, whose walls span y = -0.16 .. 0.0


def test_the_sub_task_outcome_it_names_reaches_the_parent(tmp_path):
    """Issue 31: the parent branches on which end state the round reached, `<outcome name="..."/>`."""
    shutil.copy(KNOWN_BOX / "pick_one.xml", tmp_path)
    text = (KNOWN_BOX / "empty_the_box.xml").read_text()
    task = tmp_path / "empty.xml"
    task.write_text(text.replace("<success/></transition>", '<outcome name="placed"/></transition>')
                    .replace("<error/>", '<outcome name="nothing_there"/>'))
    trace = tmp_path / "t.jsonl"
    result = atd("run", str(task), "--robot", "melfa", "--trace", str(trace), "-q")
    assert result.returncode == 0, result.stdout + result.stderr
    events = [json.loads(line) for line in trace.read_text().splitlines()]
    taken = [(r["atd"], r["conditions"]) for r in events if r["type"] == "event" and r["event"] == "outcome"]
    assert [atd for atd, _ in taken] == ["pick_one->pick_one/outcome", "pick_one->box_empty/outcome"]
    assert "nothing_there" in json.dumps(taken[1][1])


def test_the_barrett_is_refused_the_box_its_pinch_cannot_reach_into():
    """Its pinch knuckles stand where the walls are: it closed on the walls, reported the
    object held and lifted against them until the watchdog; now refused up front."""
    result = atd("run", str(KNOWN_BOX / "empty_the_box.xml"), "--robot", "tombatossals", "--arm", "right", "-q")
    assert result.returncode == 4, result.stdout
    assert "pick_one.xml" in result.stderr and "would come within 1 cm of the obstacles at (0.02, -0.08, 0.03)" in result.stderr
    assert "Traceback" not in result.stderr


def test_the_barrett_takes_the_object_out_where_the_box_would_be_in_one_round():
    """pick_one.xml alone, without the walls: grasp, lift, carry, put down at y = 0.10."""
    result = atd("run", str(KNOWN_BOX / "pick_one.xml"), "--robot", "tombatossals", "--arm", "right", "-q")
    assert result.returncode == 0 and "outcome: succeeded: reached 'placed'" in result.stdout, result.stdout
    rests = next(line for line in result.stdout.splitlines() if line.startswith("the object rests at"))
    x, y, z = (float(v) for v in rests.split("(")[1].rstrip(")").split(","))
    assert y > 0.05 and abs(x - 0.10) < 0.02 and z < 0.03  # on the table, beyond where the box's wall y = 0 stands


def test_the_naive_grasp_baseline_runs_from_the_command_line():
    result = atd("run", PICK_AND_PLACE, "--robot", "melfa", "--grasp", "naive", "-q")
    assert result.returncode == 0, result.stdout
    assert "grasp->lift/success: arm_done(arm=done" in result.stdout
    assert atd("run", PICK_AND_PLACE, "--robot", "melfa", "--grasp", "clumsy", "-q").returncode == 2
