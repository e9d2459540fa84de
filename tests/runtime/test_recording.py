"""`atd run --record`: a per-tick recording in MCAP that standard readers open."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
from mcap.reader import make_reader

from atd.model import load_task
from atd.model.files import OutputError
from atd.runtime.session import Run
from factories.registry import create
from tests.conftest import REPO
from translator import translate

TOPICS = {"/sensors", "/commands", "/task/state", "/task/trace", "/truth"}


def _record(tmp_path: Path, *args: str) -> Path:
    path = tmp_path / "run.mcap"
    result = subprocess.run([sys.executable, "-m", "atd", "run", str(REPO / "examples" / "pick_and_place.xml"),
                             "--robot", "melfa", "-q", "--record", str(path), *args],
                            capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    assert f"recording: {path}" in result.stdout
    return path


def _messages(path: Path) -> dict[str, list[tuple[int, dict]]]:
    found: dict[str, list[tuple[int, dict]]] = {}
    with path.open("rb") as f:
        for _, channel, message in make_reader(f).iter_messages():
            found.setdefault(channel.topic, []).append((message.log_time, json.loads(message.data)))
    return found


def test_a_pick_and_place_recording_holds_every_channel_at_the_asked_rate(tmp_path: Path) -> None:
    path = _record(tmp_path, "--rate", "50")
    with path.open("rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        channels = {c.topic: c for c in summary.channels.values()}
        meta = {m.name: m.metadata for m in reader.iter_metadata()}
        attachments = {a.name for a in reader.iter_attachments()}
    assert set(channels) == TOPICS | {"/truth/tf", "/truth/scene", "/tcp"}, "and Foxglove's 3D channels"
    assert channels["/truth"].metadata["ground_truth"] == "true"
    assert channels["/sensors"].metadata["ground_truth"] == "false"
    assert meta["atd.outcome"]["succeeded"] == "true"
    assert json.loads(meta["atd.run"]["value"])["robot"] == "melfa"
    assert attachments == {"task.estd.xml", "task.atd.xml"}
    messages = _messages(path)
    sim_time = float(meta["atd.outcome"]["sim_time"])
    for topic in TOPICS - {"/task/trace"}:
        times = [t for t, _ in messages[topic]]
        assert len(times) == pytest.approx(sim_time * 50, abs=2), topic
        assert max(b - a for a, b in zip(times, times[1:])) <= 20_000_000 + 10, topic
    sensors = messages["/sensors"][-1][1]
    assert set(sensors["pads"]) == {"tactile_left", "tactile_right"}
    assert len(sensors["pads"]["tactile_left"]["taxels"]) > 1, "each pad's taxel image is recorded"
    assert len(sensors["arm_q"]) == 6 and set(sensors["wrench"]) == {"force", "torque"}
    trace = [record for _, record in messages["/task/trace"]]
    assert [r["state"] for r in trace if r["type"] == "enter"][:3] == ["approach", "descend", "grasp"]
    assert any(r["type"] == "event" and r["event"] == "grasp_stable" for r in trace)
    states = {m["path"] for _, m in messages["/task/state"]}
    assert {"approach", "grasp", "carry", "let_go"} <= states
    final = messages["/truth"][-1][1]["object"]["position"]
    assert final["x"] == pytest.approx(0.10, abs=0.02) and final["y"] == pytest.approx(0.10, abs=0.02)
    held = [m for _, m in messages["/truth"] if m["pad_contacts"]]
    assert held and {c["pad"] for m in held for c in m["pad_contacts"]} == {"tactile_left", "tactile_right"}


def test_a_recording_every_tick_has_a_message_per_control_period(tmp_path: Path) -> None:
    path = _record(tmp_path, "--rate", "tick")
    times = [t for t, _ in _messages(path)["/sensors"]]
    assert {b - a for a, b in zip(times, times[1:])} == {5_000_000}, "the Melfa's control period is 5 ms"


def test_a_recording_must_be_named_mcap_and_a_bad_rate_is_refused(tmp_path: Path) -> None:
    for args, words in ((["--record", str(tmp_path / "run.json")], "ending in .mcap"),
                        (["--record", str(tmp_path / "r.mcap"), "--rate", "0"], "outside")):
        result = subprocess.run([sys.executable, "-m", "atd", "run", str(REPO / "examples" / "simple_move.xml"),
                                 "--robot", "melfa", "-q", *args], capture_output=True, text=True, timeout=120)
        assert result.returncode == 2 and words in result.stderr
        assert not list(tmp_path.iterdir())


def _simple_move(record: Path | None) -> Run:
    task, _ = load_task(REPO / "examples" / "simple_move.xml")
    factory = create("melfa")
    return Run(translate(task, factory).estd, factory, record=record, record_rate=None)


def test_recording_every_tick_leaves_the_run_as_it_was(tmp_path: Path) -> None:
    bare, recorded = _simple_move(None), _simple_move(tmp_path / "run.mcap")
    assert bare.execute().summary == recorded.execute().summary
    assert bare.trace.records == recorded.trace.records
    assert (tmp_path / "run.mcap").stat().st_size > 0


def test_a_run_that_raises_leaves_no_recording_and_no_writer_process(tmp_path: Path) -> None:
    run = _simple_move(tmp_path / "run.mcap")
    steps = 0
    step = run.robot.step

    def failing_step() -> None:
        nonlocal steps
        steps += 1
        if steps == 200:  # after several blocks of samples went to the writer
            raise RuntimeError("the engine failed")
        step()

    run.robot.step = failing_step
    writer = run.recorder.writer.pid
    with pytest.raises(RuntimeError, match="the engine failed"):
        run.execute()
    assert not list(tmp_path.iterdir()), "no recording, whole or partial"
    with pytest.raises(ChildProcessError):
        os.waitpid(writer, os.WNOHANG)  # already ended and reaped


def test_a_recording_that_cannot_be_written_says_why(tmp_path: Path) -> None:
    folder = tmp_path / "gone"
    folder.mkdir()
    run = _simple_move(folder / "run.mcap")
    folder.rmdir()  # after the run started, as when a disk is unmounted
    with pytest.raises(OutputError, match=r"cannot write .*run.mcap: the folder .*gone does not exist"):
        run.execute()
