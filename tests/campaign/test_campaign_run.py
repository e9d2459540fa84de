"""`atd campaign run` end to end, on campaigns small enough for the suite: real trials in
MuJoCo, real worker processes, a real local Ray instance."""

from __future__ import annotations

import os
import resource
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import pytest
from click.testing import CliRunner

from atd.campaign.cells import TrialPlan, plans
from atd.campaign.progress import Progress
from atd.campaign.record import TrialRecord
from atd.campaign.runner import _Pool, run_local
from atd.campaign.spec import load_spec
from atd.campaign.store import Store
from atd.campaign.trial import run_trial
from atd.cli import main
from tests.campaign.conftest import RAY_WORKERS_AT_OUR_PRIORITY, outcomes
from tests.conftest import REPO

DATA = REPO / "tests" / "data" / "campaign"


def _atd(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "atd", *args], cwd=cwd, capture_output=True, text=True, timeout=600)


def _stored(store: Path) -> int:
    with Store.open_read(store) as s:
        return len(s.records())


def _wait_for_a_stored_trial(store: Path, process: subprocess.Popen) -> None:
    """Until the campaign `process` has committed its first trial to `store`."""
    deadline = time.monotonic() + 300
    while time.monotonic() < deadline and process.poll() is None:
        if store.exists() and _stored(store):
            return
        time.sleep(0.2)


def _spec(name: str):
    loaded, found = load_spec(DATA / name)
    assert loaded is not None, found
    return loaded


@pytest.fixture(scope="module")
def straight() -> dict:
    """The small campaign run straight through in this process: the reference."""
    records: list[TrialRecord] = []
    run_local(plans(_spec("small.toml")), 1, records.append)
    return outcomes(records)


def test_the_cli_writes_every_trial_to_the_store_and_resume_skips_finished_ones(tmp_path: Path) -> None:
    store = tmp_path / "small.sqlite"
    first = _atd("campaign", "run", str(DATA / "small.toml"), "--store", str(store), "--trials", "2", "-j", "1",
                 cwd=tmp_path)
    assert first.returncode == 0, first.stderr
    with Store.open_read(store) as s:
        assert len(s.records()) == 2
    again = _atd("campaign", "run", str(DATA / "small.toml"), "--store", str(store), "--resume", "-j", "1",
                 cwd=tmp_path)
    assert again.returncode == 0, again.stderr
    assert "2 trials to run" in again.stderr and "2 already in" in again.stderr
    with Store.open_read(store) as s:
        records = s.records()
    assert sorted(r.index for r in records) == [0, 1, 2, 3]
    assert all(r.status == "ok" and r.judge_reason and "translation" in r.perturbation for r in records)


def test_an_existing_store_is_not_overwritten_without_resume(tmp_path: Path) -> None:
    store = tmp_path / "small.sqlite"
    assert _atd("campaign", "run", str(DATA / "small.toml"), "--store", str(store), "--trials", "1", "-j", "1",
                cwd=tmp_path).returncode == 0
    again = _atd("campaign", "run", str(DATA / "small.toml"), "--store", str(store), "-j", "1", cwd=tmp_path)
    assert again.returncode == 2 and "--resume" in again.stderr
    with Store.open_read(store) as s:
        assert len(s.records()) == 1


@pytest.mark.parametrize("stop", [signal.SIGKILL, signal.SIGTERM])
def test_a_campaign_killed_midway_and_resumed_equals_one_run_straight_through(tmp_path: Path, straight,
                                                                              stop: int) -> None:
    store = tmp_path / "small.sqlite"
    command = [sys.executable, "-m", "atd", "campaign", "run", str(DATA / "small.toml"), "--store", str(store),
               "-j", "1", "-q"]
    process = subprocess.Popen(command, cwd=tmp_path, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        _wait_for_a_stored_trial(store, process)
        process.send_signal(stop)
    finally:
        process.wait()
    assert 1 <= _stored(store) < 4, "the kill should land mid-campaign"
    resumed = _atd("campaign", "run", str(DATA / "small.toml"), "--store", str(store), "--resume", "-j", "1",
                   cwd=tmp_path)
    assert resumed.returncode == 0, resumed.stderr
    with Store.open_read(store) as s:
        assert outcomes(s.records()) == straight


def test_one_worker_two_workers_and_ray_give_identical_records(tmp_path: Path, straight) -> None:
    two: list[TrialRecord] = []
    run_local(plans(_spec("small.toml")), 2, two.append)
    assert outcomes(two) == straight
    # Ray through the command line, in its own process: a Ray that cannot start fails the
    # test at the timeout instead of holding the suite.
    short = tempfile.mkdtemp(prefix="ray", dir="/tmp")  # Ray's socket paths must stay under 108 bytes
    try:
        result = subprocess.run([sys.executable, "-m", "atd", "campaign", "run", str(DATA / "small.toml"),
                                 "--ray", "-j", "2", "-q", "--store", str(tmp_path / "ray.sqlite")], cwd=tmp_path,
                                capture_output=True, text=True, timeout=300,
                                env={**os.environ, "RAY_TMPDIR": short, **RAY_WORKERS_AT_OUR_PRIORITY})
    finally:
        shutil.rmtree(short, ignore_errors=True)
    assert result.returncode == 0, result.stderr
    with Store.open_read(tmp_path / "ray.sqlite") as s:
        assert outcomes(s.records()) == straight
    assert len({tuple(sorted(v["sampled"].items())) for v in straight.values()}) == 4, \
        "each trial samples its own approach error"


def test_a_trial_the_machine_ran_too_slowly_is_an_error_trial_never_a_judged_failure(monkeypatch) -> None:
    """The run's wall-clock watchdog ends a trial on a machine too slow (or too loaded) for it:
    what the judge would then read says how fast the machine was, so the trial is counted as an
    error, not as the robot's failure."""
    plan = next(iter(plans(_spec("small.toml"))))
    monkeypatch.setattr(TrialPlan, "wall_limit", property(lambda _: 0.0))  # every tick is too late
    record = run_trial(plan)
    assert record.status == "error" and not record.judged_succeeded, record
    assert "wall-clock" in record.error and "not judged" in record.error, record.error


def test_a_worker_that_dies_mid_trial_is_an_error_trial_and_the_campaign_goes_on() -> None:
    chosen = plans(_spec("small.toml"))
    records: list[TrialRecord] = []
    killed: list[int] = []

    def sink(record: TrialRecord) -> None:
        records.append(record)
        if not killed and pool.running:  # the other worker is mid-trial: crash it, as a segfault would
            pid = next(iter(pool.running))
            os.kill(pid, signal.SIGKILL)
            killed.append(pid)

    pool = _Pool(2, sink)
    pool.run(chosen)
    assert sorted(r.index for r in records) == [0, 1, 2, 3]
    errors = [r for r in records if r.status == "error"]
    # Killed just after its last report, the worker may also have taken the next plan and
    # lost a result it was still sending: at most those two trials, never a hung campaign.
    assert 1 <= len(errors) <= 2 and all("died (killed by SIGKILL)" in r.error for r in errors), errors
    assert sum(r.status == "ok" for r in records) == 4 - len(errors)


def test_a_worker_killed_while_it_waits_for_its_next_plan_holds_up_no_other() -> None:
    """Each worker waits for its plans on its own pipe. With one queue shared by all, a
    worker killed while it waited for a plan could keep the queue's lock, and the others
    waited for it forever (seen once, the test above in a suite run beside a 36-minute
    campaign: pytest idle for 35 minutes; the race did not come back on demand). Three trials
    on two workers: none holds a next plan, so the one that sends the first record waits."""
    chosen = plans(_spec("small.toml"), trials=3)
    records: list[TrialRecord] = []

    def sink(record: TrialRecord) -> None:
        records.append(record)
        if len(records) == 1:  # the worker that sent it now waits for its next plan
            [idle] = set(pool.workers) - set(pool.running)
            os.kill(idle, signal.SIGKILL)

    pool = _Pool(2, sink)
    pool.run(chosen)
    assert sorted(r.index for r in records) == [0, 1, 2]
    assert sum(r.status == "error" for r in records) <= 1


def test_a_plan_held_by_a_worker_that_dies_is_run_by_another() -> None:
    """Eight trials on two workers: each holds the plan it runs and the next. One killed at the
    first record loses the trial it ran, not the one it held."""
    records: list[TrialRecord] = []
    lost: dict[str, int] = {}

    def sink(record: TrialRecord) -> None:
        records.append(record)
        if not lost:
            pid = next(pid for pid, held in pool.queued.items() if held)
            lost.update(ran=pool.running[pid][0].index, held=pool.queued[pid][0].index)
            os.kill(pid, signal.SIGKILL)

    pool = _Pool(2, sink)
    pool.run(plans(_spec("small.toml"), trials=8))
    assert sorted(r.index for r in records) == list(range(8))
    status = {r.index: r.status for r in records}
    # One error: the trial it ran (or, had it just sent that one's record, the next it started).
    assert sum(s == "error" for s in status.values()) == 1 and "error" in (status[lost["ran"]], status[lost["held"]])


def test_the_judge_catches_a_task_that_claims_a_success_that_did_not_happen(tmp_path: Path) -> None:
    store = tmp_path / "claims.sqlite"
    result = _atd("campaign", "run", str(DATA / "claims_success.toml"), "--store", str(store), "-j", "1",
                  cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert "1 false successes" in result.stdout
    with Store.open_read(store) as s:
        (record,) = s.records()
    assert record.task_succeeded and not record.judged_succeeded and record.false_success
    assert record.judge_reason.startswith("not lifted")
    assert record.measurements["lift"] < 0.01


def test_a_bad_spec_gets_every_error_located_and_exit_1(tmp_path: Path) -> None:
    result = _atd("campaign", "run", str(DATA / "bad.toml"), cwd=tmp_path)
    assert result.returncode == 1
    lines = [line for line in result.stderr.splitlines() if "error[" in line]
    assert [line.split(": error")[0].rsplit("/", 1)[-1] for line in lines] == [
        "bad.toml:2:1", "bad.toml:3:1", "bad.toml:4:1", "bad.toml:11:1", "bad.toml:15:1"]
    assert "did you mean 'trials'?" in result.stderr
    assert "no_such_task.xml" in result.stderr and "no arm 'middle'" in result.stderr
    assert not list(tmp_path.iterdir()), "nothing is written for a spec with errors"


def test_only_narrows_the_cells_and_an_unknown_dimension_is_refused(tmp_path: Path) -> None:
    result = _atd("campaign", "run", str(DATA / "small.toml"), "--only", "colour=red", cwd=tmp_path)
    assert result.returncode == 2 and "no dimension 'colour'" in result.stderr
    result = _atd("campaign", "run", str(DATA / "small.toml"), "--only", "robot=baxter", cwd=tmp_path)
    assert result.returncode == 2 and "no cell" in result.stderr
    assert shutil.which("true") is None or not list(tmp_path.glob("*.sqlite"))


def test_a_pick_and_place_is_judged_by_where_the_object_rests(tmp_path: Path) -> None:
    records: list[TrialRecord] = []
    run_local(plans(_spec("place.toml")), 1, records.append)
    (record,) = records
    assert record.status == "ok" and record.task_succeeded, record.summary
    assert record.judged_succeeded, record.judge_reason
    assert record.measurements["distance"] < 0.02 and abs(record.measurements["height"]) < 0.01


def test_a_stop_between_storing_a_trial_and_counting_it_still_says_it_was_stored(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Ctrl-C can land after a trial is in the store and before the progress counts it: the
    message says how many the store holds (it once said one fewer, and the CI saw it)."""
    def stopped(progress: Progress, record: TrialRecord) -> None:
        raise KeyboardInterrupt
    monkeypatch.setattr(Progress, "__call__", stopped)
    store = tmp_path / "small.sqlite"
    handler = signal.getsignal(signal.SIGTERM)  # the campaign stops on SIGTERM too: give the test runner back its own
    try:
        result = CliRunner().invoke(main, ["campaign", "run", str(DATA / "small.toml"), "--store", str(store),
                                           "-j", "1", "-q", "--trials", "1"])
    finally:
        signal.signal(signal.SIGTERM, handler)
    assert result.exit_code == 130, result.stderr
    assert _stored(store) == 1 and "stopped: 1 of 1 trials were stored" in result.stderr, result.stderr


@pytest.mark.parametrize("stop", [signal.SIGINT, signal.SIGTERM])
def test_ctrl_c_or_sigterm_stops_cleanly_keeping_every_finished_trial(tmp_path: Path, stop: int) -> None:
    store = tmp_path / "small.sqlite"
    # Far more trials than can finish between the first one stored and the signal. The
    # campaign starts as from a terminal, with Ctrl-C delivered: a test run started in the
    # background by a shell (`cmd &`) ignores SIGINT, and so would the campaign it starts.
    command = [sys.executable, "-m", "atd", "campaign", "run", str(DATA / "small.toml"), "--store", str(store),
               "-j", "2", "-q", "--trials", "400"]
    process = subprocess.Popen(command, cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                               preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    _wait_for_a_stored_trial(store, process)
    assert process.poll() is None, "the campaign ended before the test could stop it"
    process.send_signal(stop)
    _, err = process.communicate(timeout=60)
    kept = _stored(store)
    assert process.returncode == 130, err
    assert 1 <= kept < 400 and f"{kept} of 400 trials were stored" in err and "--resume" in err


def test_workers_that_cannot_start_stop_the_campaign_with_a_message(tmp_path: Path) -> None:
    # A script fed on standard input cannot be re-imported by a worker process: every
    # worker dies before taking a trial, and the campaign must say so, not wait forever.
    script = ("from pathlib import Path\nfrom atd.campaign.cells import plans\nfrom atd.campaign.runner import "
              "WorkerError, run_local\nfrom atd.campaign.spec import load_spec\n"
              f"loaded, _ = load_spec(Path({str(DATA / 'small.toml')!r}))\n"
              "try:\n    run_local(plans(loaded), 2, print)\nexcept WorkerError as exc:\n    print('stopped:', exc)\n")
    result = subprocess.run([sys.executable, "-"], input=script, cwd=tmp_path, capture_output=True, text=True,
                            timeout=120)
    assert "stopped: a worker process could not start (exit code 1)" in result.stdout, result.stderr


def test_a_pool_worker_loads_no_engine_and_compiles_no_model_on_its_first_trial() -> None:
    # A worker is forked from a server that has imported WORKER_PRELOAD: building its first
    # trial then imports no engine and compiles no model template (each worker did both, 0.54 G
    # instructions of its first trial; docs/campaigns.md). Counted in a fresh Python.
    script = ("import importlib, sys\nfrom pathlib import Path\nimport jinja2\n"
              "from atd.campaign.runner import WORKER_PRELOAD\nimportlib.import_module(WORKER_PRELOAD)\n"
              "from atd.campaign.cells import plans\nfrom atd.campaign.record import TrialRecord\n"
              "from atd.campaign.spec import load_spec\nfrom atd.campaign.trial import trial_run\n"
              "compiled = []\ncompile_ = jinja2.Environment.compile\n"
              "jinja2.Environment.compile = lambda *a, **k: compiled.append(1) or compile_(*a, **k)\n"
              f"plan = next(iter(plans(load_spec(Path({str(DATA / 'small.toml')!r}))[0])))\n"
              "before = set(sys.modules)\n"
              "trial_run(plan, TrialRecord(cell=plan.cell, index=plan.index, seed=plan.seed))\n"
              "print(len(compiled), sorted(m for m in set(sys.modules) - before if m.startswith(('mujoco', 'OpenGL', 'atd.sim'))))\n")
    result = subprocess.run([sys.executable, "-"], input=script, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert result.stdout.split("\n")[0] == "0 []"


def test_the_trials_the_judge_fails_are_recorded_for_atd_report(tmp_path: Path) -> None:
    folder = tmp_path / "failed"
    folder.mkdir()
    result = _atd("campaign", "run", str(DATA / "claims_success.toml"), "--store", str(tmp_path / "c.sqlite"),
                  "-j", "1", "--record-failed", str(folder), cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    (recording,) = folder.iterdir()
    with Store.open_read(tmp_path / "c.sqlite") as s:
        campaign = s.campaign
    assert recording.name == f"claims_success-{campaign}__claims_success__melfa__main__mujoco__robust__task__none__0.mcap"
    page = _atd("report", str(recording), "-o", str(tmp_path / "r.html"), cwd=tmp_path)
    assert page.returncode == 0, page.stderr
    assert "grasp_object" in (tmp_path / "r.html").read_text()


def _files_limited_to(size: int):
    """A child's `ulimit -f`: a write past `size` bytes fails with EFBIG (Python ignores SIGXFSZ)."""
    return lambda: resource.setrlimit(resource.RLIMIT_FSIZE, (size, resource.getrlimit(resource.RLIMIT_FSIZE)[1]))


def test_a_campaign_stopped_by_the_file_size_limit_and_resumed_equals_one_run_straight_through(
        tmp_path: Path, straight) -> None:
    """32 KiB holds the new store and a few trials' write-ahead log, not the whole campaign."""
    store = tmp_path / "small.sqlite"
    command = ["campaign", "run", str(DATA / "small.toml"), "--store", str(store), "-j", "1", "-q"]
    limited = subprocess.run([sys.executable, "-m", "atd", *command], cwd=tmp_path, capture_output=True, text=True,
                             timeout=600, preexec_fn=_files_limited_to(32 * 1024))
    assert limited.returncode == 2 and "file-size limit" in limited.stderr, limited.stderr
    assert 1 <= _stored(store) < 4, "the limit should land mid-campaign"
    resumed = _atd(*command, "--resume", cwd=tmp_path)
    assert resumed.returncode == 0, resumed.stderr
    with Store.open_read(store) as s:
        assert outcomes(s.records()) == straight


def test_a_recording_that_cannot_be_written_costs_the_trial_nothing(tmp_path: Path) -> None:
    """Under a 40 KiB file-size limit the store is written, each trial's 54 KB recording is not:
    a warning each, the trial stored as it ran, exit 2 at the end (was a traceback, and with two
    workers the trial stored as 'the worker process died')."""
    folder = tmp_path / "failed"
    folder.mkdir()
    store = tmp_path / "c.sqlite"
    result = subprocess.run([sys.executable, "-m", "atd", "campaign", "run", str(DATA / "claims_success.toml"),
                             "--store", str(store), "--trials", "2", "-j", "1", "--record-failed", str(folder)],
                            cwd=tmp_path, capture_output=True, text=True, timeout=600,
                            preexec_fn=_files_limited_to(40 * 1024))
    assert result.returncode == 2, result.stderr
    warnings = [line for line in result.stderr.splitlines() if line.startswith("warning:")]
    assert len(warnings) == 2 and all("is stored, its recording is not" in w and "ulimit -f" in w for w in warnings)
    assert "2 failed trials are stored but not recorded" in result.stderr and "Traceback" not in result.stderr
    with Store.open_read(store) as s:
        records = s.records()
    assert [(r.index, r.status, r.false_success) for r in records] == [(0, "ok", True), (1, "ok", True)]
    assert list(folder.iterdir()) == []


def test_with_two_workers_a_lost_recording_leaves_the_records_as_they_are_without_one(tmp_path: Path) -> None:
    chosen = plans(_spec("claims_success.toml"), trials=2)
    plain: list[TrialRecord] = []
    run_local(chosen, 1, plain.append)
    recorded: list[TrialRecord] = []
    run_local(replace(chosen, recordings=tmp_path / "missing", campaign="c"), 2, recorded.append)
    assert outcomes(recorded) == outcomes(plain)
    assert all("cannot write" in r.recording_error and "missing" in r.recording_error for r in recorded)
