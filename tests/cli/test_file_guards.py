"""Issue 12: nothing a user names as a file loses data, hangs the command or leaves a half-written file."""

from __future__ import annotations

import ctypes
import errno
import os
import resource
import shutil
import signal
import subprocess
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner

from atd.campaign.store import Store
from atd.cli import main

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
KNOWN_BOX = EXAMPLES.parent / "tests" / "data" / "known_box"
CAMPAIGN_SPEC = EXAMPLES.parent / "tests" / "data" / "campaign" / "small.toml"
PR_CAPBSET_DROP, CAP_DAC_OVERRIDE, CAP_DAC_READ_SEARCH = 24, 1, 2  # linux/prctl.h, linux/capability.h


@pytest.fixture
def task(tmp_path: Path) -> Path:
    path = tmp_path / "move.xml"
    shutil.copy(EXAMPLES / "simple_move.xml", path)
    return path


def atd(*args: object) -> object:
    return CliRunner().invoke(main, [str(a) for a in args])


def leftovers(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if p.name.startswith("."))


def test_translate_refuses_to_overwrite_its_own_task(task: Path) -> None:
    before = task.read_bytes()
    result = atd("translate", task, "--robot", "melfa", "-o", task)
    assert result.exit_code == 2
    assert "input of this command" in result.output
    assert task.read_bytes() == before


def test_run_refuses_a_trace_over_its_task(task: Path) -> None:
    before = task.read_bytes()
    result = atd("run", task, "--robot", "melfa", "--trace", task)
    assert result.exit_code == 2 and "input of this command" in result.output
    assert task.read_bytes() == before


def test_trace_and_video_naming_one_file_are_refused_and_leave_nothing(task: Path) -> None:
    out = task.with_name("run.gif")
    result = atd("run", task, "--robot", "melfa", "--trace", out, "--video", out)
    assert result.exit_code == 2 and "names the same file" in result.output
    assert not out.exists() and leftovers(task.parent) == []


def test_an_output_that_is_not_a_regular_file_is_never_replaced(task: Path) -> None:
    fifo = task.with_name("pipe.xml")
    os.mkfifo(fifo)
    result = atd("translate", task, "--robot", "melfa", "-o", fifo)
    assert result.exit_code == 2 and "not a regular file" in result.output
    assert fifo.is_fifo()


def test_a_rejected_video_name_leaves_no_partial_trace(task: Path) -> None:
    result = atd("run", task, "--robot", "melfa", "--trace", task.with_name("t.jsonl"),
                 "--video", task.with_name("run.avi"))
    assert result.exit_code == 2 and "*.gif or *.mp4" in result.output
    assert sorted(p.name for p in task.parent.iterdir()) == ["move.xml"]


def test_an_option_given_twice_is_refused(task: Path) -> None:
    result = atd("translate", task, "--robot", "melfa", "-o", task.with_name("a.xml"), "-o", task.with_name("b.xml"))
    assert result.exit_code == 2 and "more than once" in result.output
    assert sorted(p.name for p in task.parent.iterdir()) == ["move.xml"]


def _limited_file_size() -> None:
    """In the child: files of at most 100 bytes, and a write past that fails with EFBIG
    instead of killing the process (SIGXFSZ ignored, as a shell's `ulimit -f` user sees it)."""
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (100, 100))


WRITING_COMMANDS = [["translate", "--robot", "melfa", "-q", "-o", "out.xml"],
                    ["graph", "-o", "out.svg"],
                    ["run", "--robot", "melfa", "-q", "--trace", "out.jsonl"],
                    ["run", "--robot", "melfa", "-q", "--record", "out.mcap"],
                    ["run", "--robot", "melfa", "-q", "--video", "out.gif"]]


@pytest.mark.parametrize("command", [*WRITING_COMMANDS, ["run", "--robot", "melfa", "-q", "--video", "out.mp4"]])
def test_a_file_size_limit_is_one_line_exit_2_and_nothing_left(task: Path, command: list[str]) -> None:
    done = subprocess.run([sys.executable, "-m", "atd", command[0], str(task), *command[1:]], cwd=task.parent,
                          capture_output=True, text=True, preexec_fn=_limited_file_size, timeout=120)
    assert done.returncode == 2, done.stderr
    assert done.stderr.strip().count("\n") == 0 and "File too large" in done.stderr
    assert "ulimit -f" in done.stderr and command[-1] in done.stderr
    assert sorted(p.name for p in task.parent.iterdir()) == ["move.xml"]


@pytest.mark.parametrize("command", WRITING_COMMANDS)
def test_a_full_disk_is_one_line_exit_2_and_nothing_left(task: Path, command: list[str], monkeypatch) -> None:
    """ENOSPC as a file system reports it when the data reach the disk: at the flush before
    the output replaces anything."""
    def disk_full(fd: int) -> None:
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(os, "fsync", disk_full)
    monkeypatch.chdir(task.parent)
    result = CliRunner().invoke(main, [command[0], str(task), *command[1:]])
    assert result.exit_code == 2, result.output
    assert result.stderr.strip().count("\n") == 0 and "No space left on device" in result.stderr
    assert "free some space" in result.stderr and command[-1] in result.stderr
    assert sorted(p.name for p in task.parent.iterdir()) == ["move.xml"]


@pytest.mark.parametrize("command", [["validate"], ["graph", "-o", "{out}"], ["run", "--robot", "melfa"],
                                     ["check"]])
def test_a_fifo_as_the_task_is_refused_at_once(tmp_path: Path, command: list[str]) -> None:
    fifo = tmp_path / "task.xml"
    os.mkfifo(fifo)
    args = [a.format(out=tmp_path / "g.svg") for a in command]
    done = subprocess.run([sys.executable, "-m", "atd", args[0], str(fifo), *args[1:]], capture_output=True,
                          text=True, timeout=30)
    assert done.returncode == 1
    said = done.stdout + done.stderr
    assert "invalid ATD" in said if command == ["check"] else "ATD001" in said and "not a regular file" in said


@pytest.mark.parametrize("device", ["/dev/zero", "/dev/urandom"])
def test_an_endless_device_is_refused_without_reading_it(device: str) -> None:
    result = atd("validate", device)
    assert result.exit_code == 1 and "ATD001" in result.output


def test_a_missing_task_is_atd001_and_exit_1_for_run(tmp_path: Path) -> None:
    result = atd("run", tmp_path / "nosuch.xml", "--robot", "melfa")
    assert result.exit_code == 1 and "ATD001" in result.output


def test_names_over_255_bytes_are_located_errors_in_every_command(tmp_path: Path) -> None:
    long = "a" * 300
    task = tmp_path / "long.xml"
    task.write_text(f"""<statemachine>
  <object><shape>{long}.stl</shape></object>
  <state name="s" type="task" file="{long}.xml"/>
  <state name="done" type="success"/>
  <transition origin="s" destination="done"><success/></transition>
</statemachine>""")
    for args in (["validate"], ["check"], ["graph", "-o", tmp_path / "g.svg"], ["translate", "-r", "melfa"],
                 ["run", "-r", "melfa"]):
        result = atd(args[0], task, *args[1:])
        assert result.exit_code == 1, (args, result.output)
        assert result.exception is None or isinstance(result.exception, SystemExit)
    result = atd("validate", task)
    assert "long.xml:2:11: error[ATD112]" in result.output and "long.xml:3:3: error[ATD112]" in result.output


def test_an_output_name_over_255_bytes_is_refused(task: Path) -> None:
    result = atd("translate", task, "--robot", "melfa", "-o", task.with_name("b" * 300 + ".xml"))
    assert result.exit_code == 2 and "over the 255" in result.output


@pytest.mark.parametrize("command", [["translate", "{path}", "--robot", "melfa"], ["report", "{path}"]])
@pytest.mark.parametrize("path", [".", "/"])
def test_a_folder_as_the_input_of_a_command_with_a_default_output_is_refused_as_input(command: list[str],
                                                                                        path: str) -> None:
    """The default output is named after the input, once that input has been read as a file."""
    result = atd(*(a.format(path=path) for a in command))
    assert result.exit_code == 1 and "directory" in result.output
    assert result.exception is None or isinstance(result.exception, SystemExit)


def test_unknown_robot_for_robots_test_is_a_usage_error() -> None:
    assert atd("robots", "test", "nosuch").exit_code == 2


def test_a_sub_task_or_mesh_of_the_task_is_never_an_output(tmp_path: Path) -> None:
    for name in ("empty_the_box.xml", "pick_one.xml"):
        shutil.copy(KNOWN_BOX / name, tmp_path)
    sub = tmp_path / "pick_one.xml"
    before = sub.read_bytes()
    task = str(tmp_path / "empty_the_box.xml")
    assert atd("translate", task, "--robot", "melfa", "-o", sub).exit_code == 2
    assert atd("run", task, "--robot", "melfa", "--trace", sub).exit_code == 2
    assert sub.read_bytes() == before


def _without_root_file_access() -> None:
    """In the child: no permission bypass, so a read-only folder refuses root as it refuses
    anyone (root is otherwise exempt, and CI runs as root). The capabilities that bypass file
    permissions leave the bounding set, so the command exec'd next never gets them."""
    if os.geteuid() != 0:
        return
    libc = ctypes.CDLL(None, use_errno=True)
    for capability in (CAP_DAC_OVERRIDE, CAP_DAC_READ_SEARCH):
        if libc.prctl(PR_CAPBSET_DROP, capability, 0, 0, 0) != 0:
            raise OSError(ctypes.get_errno(), "prctl(PR_CAPBSET_DROP) failed")


@pytest.fixture
def read_only(tmp_path: Path) -> Path:
    folder = tmp_path / "read_only"
    folder.mkdir()
    folder.chmod(0o555)
    yield folder
    folder.chmod(0o755)


def _store(folder: Path) -> Path:
    path = folder / "done.sqlite"
    Store.create_or_resume(path, "[campaign]\n", "digest", resume=False).close()
    return path


@pytest.mark.parametrize("command", [
    ["translate", "{task}", "--robot", "melfa", "-o", "{out}/out.xml"],
    ["graph", "{task}", "-o", "{out}/out.svg"],
    ["run", "{task}", "--robot", "melfa", "--trace", "{out}/out.jsonl"],
    ["campaign", "run", "{spec}", "--store", "{out}/c.sqlite"],
    ["campaign", "run", "{spec}"],  # the store's default place: the current folder
    ["campaign", "export", "{store}", "--format", "csv", "-o", "{out}/c.csv"],
    ["campaign", "report", "{store}", "-o", "{out}/report.txt"],
])
def test_no_permission_to_write_is_one_line_exit_2_and_nothing_left(task: Path, read_only: Path,
                                                                  command: list[str]) -> None:
    """A real EACCES: the folder is read-only and the command runs without root's bypass."""
    names = {"task": task, "out": read_only, "spec": CAMPAIGN_SPEC, "store": _store(task.parent)}
    done = subprocess.run([sys.executable, "-m", "atd", *(a.format(**names) for a in command)], cwd=read_only,
                          capture_output=True, text=True, preexec_fn=_without_root_file_access, timeout=120)
    assert done.returncode == 2, done.stderr
    assert done.stderr.strip().count("\n") == 0 and "not writable" in done.stderr
    assert str(read_only) in done.stderr or "read_only" in done.stderr
    assert list(read_only.iterdir()) == []


def test_a_campaign_store_over_the_file_size_limit_is_one_line_exit_2_and_nothing_left(tmp_path: Path) -> None:
    done = subprocess.run([sys.executable, "-m", "atd", "campaign", "run", str(CAMPAIGN_SPEC), "-q"], cwd=tmp_path,
                          capture_output=True, text=True, preexec_fn=_limited_file_size, timeout=120)
    assert done.returncode == 2, done.stderr
    assert done.stderr.strip().count("\n") == 0 and "cannot write" in done.stderr and "file-size limit" in done.stderr
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("command", [
    ["campaign", "report", "{store}", "-o", "{store}"],
    ["campaign", "export", "{store}", "--format", "csv", "-o", "{store}"],
    ["campaign", "report", "{store}", "--plot", "{dir}/r.svg", "-o", "{dir}/r.svg"],
    ["campaign", "run", "{store}", "--store", "{store}"],
    ["report", "{store}", "-o", "{store}"],
    ["compare", "{store}", "{dir}/b.mcap", "--plot", "{store}"],
])
def test_no_command_writes_over_a_file_its_command_line_reads(tmp_path: Path, command: list[str]) -> None:
    store = _store(tmp_path)
    before = store.read_bytes()
    result = atd(*(a.format(store=store, dir=tmp_path) for a in command))
    assert result.exit_code == 2, result.output
    assert store.read_bytes() == before and sorted(p.name for p in tmp_path.iterdir()) == ["done.sqlite"]


def test_the_default_report_name_is_never_the_recording_itself(tmp_path: Path, monkeypatch) -> None:
    recording = tmp_path / "run.html"
    recording.write_bytes(b"a recording named .html")
    monkeypatch.setattr("atd.cli.review.load", lambda path: "a run read from it")
    result = atd("report", recording)
    assert result.exit_code == 2 and "input of this command" in result.output
    assert recording.read_bytes() == b"a recording named .html"


@pytest.mark.parametrize("option", [["-j", "100000"], ["-j", "0"], ["--trials", "nan"], ["--trials", "-3"]])
def test_campaign_counts_outside_their_range_are_refused_before_any_work(tmp_path: Path, option: list[str]) -> None:
    result = atd("campaign", "run", CAMPAIGN_SPEC, "--store", tmp_path / "c.sqlite", *option)
    assert result.exit_code == 2 and "[1, " in result.output
    assert list(tmp_path.iterdir()) == []


def test_a_symlink_loop_named_anywhere_is_one_line_not_a_traceback(task: Path) -> None:
    """A loop named as a campaign's task, a task's mesh or a folder to record into."""
    loop = task.parent / "loop"
    loop.symlink_to(loop)
    spec = task.parent / "spec.toml"
    spec.write_text(CAMPAIGN_SPEC.read_text().replace("../../../examples/grasp_and_lift.xml", "loop"))
    meshed = task.parent / "meshed.xml"
    meshed.write_text(task.read_text().replace("<class>", "<shape>loop</shape><class>"))
    for command, code, said in [(["campaign", "run", spec, "--store", task.parent / "c.sqlite"], 1, "CMP020"),
                                (["run", meshed, "--robot", "melfa"], 1, "shape 'loop'"),
                                (["campaign", "run", CAMPAIGN_SPEC, "--record-failed", loop], 2, "--record-failed")]:
        result = atd(*command)
        assert (result.exit_code, type(result.exception)) == (code, SystemExit), result.output
        assert said in result.output
    assert sorted(p.name for p in task.parent.iterdir()) == ["loop", "meshed.xml", "move.xml", "spec.toml"]


@pytest.mark.parametrize("resume", [[], ["--resume"]])
def test_a_campaign_store_is_never_one_of_the_spec_s_tasks(task: Path, resume: list[str]) -> None:
    spec = task.parent / "spec.toml"
    spec.write_text(CAMPAIGN_SPEC.read_text().replace("../../../examples/grasp_and_lift.xml", task.name))
    before = task.read_bytes()
    result = atd("campaign", "run", spec, "--store", task, *resume)
    assert result.exit_code == 2 and "input of this command" in result.output, result.output
    assert task.read_bytes() == before and sorted(p.name for p in task.parent.iterdir()) == ["move.xml", "spec.toml"]


def test_each_output_problem_is_said_once_and_in_its_own_words(task: Path) -> None:
    result = atd("compare", task, task, "--plot", task)
    assert result.exit_code == 2 and result.output.count("input of this command") == 1, result.output
    result = atd("translate", task, "--robot", "melfa", "-o", task / "out.xml")
    assert result.exit_code == 2 and f"{task} is not a folder" in result.output


def test_a_sub_task_or_mesh_that_is_no_file_is_named_for_what_it_is(tmp_path: Path) -> None:
    shutil.copy(KNOWN_BOX / "empty_the_box.xml", tmp_path)
    shutil.copy(EXAMPLES / "simple_move.xml", tmp_path)
    (tmp_path / "folder.xml").mkdir()
    os.mkfifo(tmp_path / "pipe.obj")
    task = tmp_path / "empty_the_box.xml"
    task.write_text(task.read_text().replace('file="pick_one.xml"', 'file="folder.xml"'))
    meshed = tmp_path / "simple_move.xml"
    meshed.write_text(meshed.read_text().replace("<class>", "<shape>pipe.obj</shape><class>"))
    result = atd("validate", task, meshed)
    assert result.exit_code == 1
    assert "error[ATD211]: sub-task file 'folder.xml' of state 'pick_one': is a directory" in result.output
    assert "error[ATD216]: object shape 'pipe.obj': is not a regular file" in result.output


@pytest.mark.parametrize("kind", ["missing", "folder", "fifo"])
def test_an_unreadable_config_or_campaign_spec_is_invalid_input_exit_1(task: Path, kind: str) -> None:
    """click refused a missing or folder --config and SPEC with exit 2, a FIFO got exit 1."""
    path = task.parent / "given.toml"
    if kind == "folder":
        path.mkdir()
    elif kind == "fifo":
        os.mkfifo(path)
    said = {"missing": "no such file", "folder": "is a directory", "fifo": "not a regular file"}[kind]
    for command in (["translate", task, "--robot", "melfa", "--config", path], ["campaign", "run", path]):
        result = atd(*command)
        assert result.exit_code == 1 and said in result.output, (command, result.output)
