"""The campaign store keeps every finished trial, refuses to mix campaigns, and says why."""

from __future__ import annotations

import os
import resource
import signal
import sqlite3
import subprocess
import sys
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator

import pytest

from atd.campaign.store import CAMPAIGN_ID, Store, StoreError
from tests.campaign.conftest import approach, preset_records, trial

SPEC = "[campaign]\ntrials = 4\n"


def test_records_come_back_as_they_went_in_ordered_by_cell_then_index(tmp_path: Path) -> None:
    records = preset_records()
    records[3].status, records[3].error = "error", "worker crashed"
    path = tmp_path / "c.sqlite"
    with Store.create_or_resume(path, SPEC, "d1", resume=False) as store:
        for record in reversed(records):
            store.add(record)
    with Store.open_read(path) as store:
        back = store.records()
        assert store.spec_text == SPEC and store.spec_digest == "d1"
    assert back == sorted(records, key=lambda r: (r.cell.key, r.index))
    assert back[0].perturbation == approach(0.01, 3.0)  # the sampled values survive, not only the cell's name


def test_counts_and_indices_name_the_finished_trials_of_each_cell(tmp_path: Path) -> None:
    with Store.create_or_resume(tmp_path / "c.sqlite", SPEC, "d1", resume=False) as store:
        assert store.counts(10) == {}
        for record in (trial(0), trial(1, status="error"), trial(5), trial(0, grasp="robust")):
            store.add(record)
        cell, robust = trial().cell, trial(grasp="robust").cell
        assert store.counts(10) == {cell.key: 3, robust.key: 1}
        assert store.counts(2) == {cell.key: 2, robust.key: 1}, "only the trials numbered below the count asked for"
        assert store.indices(cell, 10) == {0, 1, 5} and store.indices(cell, 5) == {0, 1}


def test_resume_continues_the_same_store(tmp_path: Path) -> None:
    path = tmp_path / "c.sqlite"
    with Store.create_or_resume(path, SPEC, "d1", resume=False) as store:
        store.add(trial(0))
    with Store.create_or_resume(path, SPEC, "d1", resume=True) as store:
        store.add(trial(1))
        assert [r.index for r in store.records()] == [0, 1]


def test_an_existing_store_is_not_overwritten_without_resume(tmp_path: Path) -> None:
    path = tmp_path / "c.sqlite"
    Store.create_or_resume(path, SPEC, "d1", resume=False).close()
    with pytest.raises(StoreError, match="exists; add --resume to continue it, or give another --store"):
        Store.create_or_resume(path, SPEC, "d1", resume=False)


def test_a_store_another_campaign_is_writing_is_refused_until_it_ends(tmp_path: Path) -> None:
    """A resume started in a second terminal would run the first one's trials again."""
    path = tmp_path / "c.sqlite"
    with Store.create_or_resume(path, SPEC, "d1", resume=False) as first:
        with pytest.raises(StoreError, match="is being written by another campaign; wait for it to end"):
            Store.create_or_resume(path, SPEC, "d1", resume=True)
        first.add(trial(0))
        with Store.open_read(path) as report:  # a report may read it meanwhile
            assert len(report.records()) == 1
    with Store.create_or_resume(path, SPEC, "d1", resume=True) as second:
        second.add(trial(1))


def test_resume_refuses_a_store_made_from_another_spec(tmp_path: Path) -> None:
    path = tmp_path / "c.sqlite"
    with Store.create_or_resume(path, SPEC, "d1", resume=False) as store:
        store.add(trial(0))
    with pytest.raises(StoreError, match="made from a different spec"):
        Store.create_or_resume(path, SPEC + "# changed\n", "d2", resume=True)
    with Store.open_read(path) as store:
        assert len(store.records()) == 1


def test_resume_keeps_the_campaign_id_and_refuses_other_task_content(tmp_path: Path) -> None:
    path = tmp_path / "c.sqlite"
    with Store.create_or_resume(path, SPEC, "d1", False, {"t.xml": "aa", "sub.xml": "bb"}) as store:
        assert CAMPAIGN_ID.fullmatch(store.campaign)
        campaign = store.campaign
    with Store.create_or_resume(path, SPEC, "d1", True, {"t.xml": "aa", "sub.xml": "bb"}) as store:
        assert store.campaign == campaign and not store.keyed_now, "a resumed campaign's recordings keep their names"
    for tasks in ({"t.xml": "aa", "sub.xml": "cc"}, {"t.xml": "aa"}):
        with pytest.raises(StoreError, match=r"sub.xml \(relative to the spec\) has changed since; --resume would mix"):
            Store.create_or_resume(path, SPEC, "d1", True, tasks)


def test_a_store_made_before_stores_were_keyed_to_their_tasks_is_keyed_at_its_next_resume(tmp_path: Path) -> None:
    path = tmp_path / "c.sqlite"
    with Store.create_or_resume(path, SPEC, "d1", resume=False) as store:
        store.add(trial(0))
    db = sqlite3.connect(path)
    with db:
        db.execute("DELETE FROM meta WHERE key IN ('task_digests', 'campaign')")
    db.close()
    with Store.open_read(path) as store:
        assert store.task_digests is None and store.campaign is None and len(store.records()) == 1
    with Store.create_or_resume(path, SPEC, "d1", True, {"t.xml": "aa"}) as store:
        assert store.keyed_now and store.task_digests == {"t.xml": "aa"} and CAMPAIGN_ID.fullmatch(store.campaign)
    with pytest.raises(StoreError, match="t.xml"):
        Store.create_or_resume(path, SPEC, "d1", True, {"t.xml": "changed"})


def test_a_trial_stored_twice_is_refused(tmp_path: Path) -> None:
    with Store.create_or_resume(tmp_path / "c.sqlite", SPEC, "d1", resume=False) as store:
        store.add(trial(0))
        with pytest.raises(StoreError, match="trial 0 of cell .* is already stored"):
            store.add(trial(0))


@contextmanager
def files_limited_to(size: int) -> Iterator[None]:
    """A file-size limit (`ulimit -f`) on this process for the block; a write past it fails
    with EFBIG, as the shell's user sees it."""
    soft, hard = resource.getrlimit(resource.RLIMIT_FSIZE)
    handler = signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (size, hard))
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_FSIZE, (soft, hard))
        signal.signal(signal.SIGXFSZ, handler)


def test_a_store_that_cannot_be_written_is_a_store_error_not_a_traceback(tmp_path: Path) -> None:
    """A full disk or a size limit while a campaign stores its trials: StoreError, which the
    command reports in one line, keeping the trials stored before."""
    with Store.create_or_resume(tmp_path / "c.sqlite", SPEC, "d1", resume=False) as store:
        store.add(trial(0))
        with files_limited_to(100), pytest.raises(StoreError, match="cannot write .*c.sqlite: .*write elsewhere"):
            store.add(trial(1))
        assert [r.index for r in store.records()] == [0]
    with files_limited_to(100), pytest.raises(StoreError, match="cannot write .*new.sqlite"):
        Store.create_or_resume(tmp_path / "new.sqlite", SPEC, "d1", resume=False)
    assert sorted(p.name for p in tmp_path.iterdir() if "new" in p.name) == []


def test_store_paths_that_cannot_hold_a_store_are_refused(tmp_path: Path) -> None:
    with pytest.raises(StoreError, match="is not a regular file"):
        Store.create_or_resume(tmp_path, SPEC, "d1", resume=True)
    with pytest.raises(StoreError, match="the folder .*missing does not exist"):
        Store.create_or_resume(tmp_path / "missing" / "c.sqlite", SPEC, "d1", resume=False)


def test_reading_a_missing_file_or_a_file_that_is_no_store_says_so(tmp_path: Path) -> None:
    with pytest.raises(StoreError, match="no such file"):
        Store.open_read(tmp_path / "nowhere.sqlite")
    text = tmp_path / "notes.txt"
    text.write_text("not a database\n" * 100)
    with pytest.raises(StoreError, match="notes.txt is not a campaign store"):
        Store.open_read(text)
    other = tmp_path / "other.sqlite"
    with sqlite3.connect(other) as db:
        db.execute("CREATE TABLE things (x)")
    with pytest.raises(StoreError, match="other.sqlite is not a campaign store"):
        Store.open_read(other)


@pytest.mark.parametrize("damage", [
    "UPDATE meta SET value = CAST(x'ff' AS TEXT) WHERE key = 'format_version'",  # not UTF-8: a traceback before
    "UPDATE trials SET events = '[{' WHERE \"index\" = 0",
    "UPDATE trials SET sampled = CAST(x'fe' AS TEXT) WHERE \"index\" = 0",
])
def test_a_damaged_store_is_a_store_error_not_a_traceback(tmp_path: Path, damage: str) -> None:
    path = tmp_path / "c.sqlite"
    with Store.create_or_resume(path, SPEC, "d1", resume=False) as store:
        for record in preset_records():
            store.add(record)
    with sqlite3.connect(path) as db:
        db.execute(damage)
    with pytest.raises(StoreError, match="is not a campaign store|the store is damaged"):
        with Store.open_read(path) as store:
            store.records()


def test_a_store_from_a_newer_atd_is_refused_not_misread(tmp_path: Path) -> None:
    path = tmp_path / "c.sqlite"
    Store.create_or_resume(path, SPEC, "d1", resume=False).close()
    db = sqlite3.connect(path)
    with db:
        db.execute("UPDATE meta SET value = '99' WHERE key = 'format_version'")
    db.close()
    with pytest.raises(StoreError, match="store format 99, newer than this atd reads .*upgrade atd"):
        Store.open_read(path)


_WRITER = """
import sys, time
from pathlib import Path
from atd.campaign.store import Store
from tests.campaign.conftest import trial
store = Store.create_or_resume(Path(sys.argv[1]), "spec", "d1", resume=False)
for i in range(1000):
    store.add(trial(i))
    print(i, flush=True)
    time.sleep(0.01)
"""


def test_a_killed_campaign_keeps_every_trial_it_committed(tmp_path: Path) -> None:
    path = tmp_path / "c.sqlite"
    repo = Path(__file__).resolve().parents[2]
    writer = subprocess.Popen([sys.executable, "-c", _WRITER, str(path)], cwd=repo, stdout=subprocess.PIPE,
                              text=True, env={**os.environ, "PYTHONPATH": str(repo)})
    assert writer.stdout is not None
    committed = [int(writer.stdout.readline()) for _ in range(20)]
    writer.send_signal(signal.SIGKILL)
    writer.wait()
    assert Path(f"{path}-wal").exists()  # killed: the write-ahead log was never checkpointed
    with Store.open_read(path) as store:
        stored = [r.index for r in store.records()]
    assert stored[:20] == committed
    assert stored == list(range(len(stored)))
