"""Hostile campaigns, replayed: seeded samples of the ways issue 30 broke a campaign (specs
whose cells collide or mean nothing, damaged stores, two campaigns making one store, edited
tasks, unwritable recordings, huge specs). Each must end in located diagnostics or one
line, exit 1 or 2, with nothing written, lost or overwritten and no traceback. No trial is
simulated: every case is refused before the first one."""

from __future__ import annotations

import os
import random
import shutil
import sqlite3
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest
from click.testing import CliRunner

from atd.campaign import store as store_module
from atd.campaign.cells import plans, trial_seed
from atd.campaign.record import Cell, TrialRecord
from atd.campaign.spec import load_spec
from atd.campaign.store import DamagedStore, Store, StoreError
from atd.cli import main
from tests.campaign.conftest import preset_records
from tests.conftest import REPO

DATA = REPO / "tests" / "data" / "campaign"
TASK = (DATA / "claims_success.xml").read_text()
SPEC = 'name = "h"\ntrials = 1\ntasks = [{tasks}]\nrobots = [{robots}]\n{extra}\n'


def _atd(*args: str) -> tuple[int, str]:
    result = CliRunner().invoke(main, list(args))
    return result.exit_code, result.stderr


# --- specs: every entry that would make cells collide or the campaign meaningless --------------

def _setup_spec(folder: Path) -> None:
    (folder / "a").mkdir()
    (folder / "b").mkdir()
    for name in ("task.xml", "a/lift.xml", "b/lift.xml"):
        (folder / name).write_text(TASK)
    (folder / "broken.xml").write_text("<statemachine><state name='s' type='nonsense'/></statemachine>\n")
    os.mkfifo(folder / "fifo.xml")


#: One hostile edit each: (tasks, robots, extra TOML, the codes it must bring, words in them).
HOSTILE_SPECS = [
    ('"task.xml", "task.xml"', '"melfa"', "", {"CMP024"}, "listed twice"),
    ('"a/lift.xml", "b/lift.xml"', '"melfa"', "", {"CMP025"}, "both make cells named 'lift'"),
    ('"task.xml"', '"melfa", "melfa"', "", {"CMP024"}, "'melfa' with arm 'main' is listed twice"),
    ('"task.xml"', '"baxter", {name = "baxter", arms = ["right"]}', "", {"CMP024"}, "listed twice"),
    ('"task.xml"', '{name = "tombatossals", arms = ["left", "left"]}', "", {"CMP024"}, "listed twice"),
    ('"task.xml"', '"melfa"', 'objects = ["mug", "task", "mug"]', {"CMP024"}, "objects lists 'mug' twice"),
    ('"task.xml"', '"melfa"', 'engines = ["mujoco", "mujoco"]', {"CMP024"}, "twice"),
    ('"task.xml"', '"melfa"', 'grasps = ["naive", "naive"]', {"CMP024"}, "twice"),
    ('"broken.xml"', '"melfa"', "", {"CMP026"}, "does not validate"),
    ('"fifo.xml"', '"melfa"', "", {"CMP020"}, "not a regular file"),
    ('"/dev/zero"', '"melfa"', "", {"CMP020"}, "not a regular file"),
    ('"a"', '"melfa"', "", {"CMP020"}, "is a directory"),
    ('"task.xml"', '"melfa"', '[perturbations.p]\nmodel = "approach"\ntranslation = nan', {"CMP012"},
     "nan is not a finite number; give one in [0, 0.2] m"),
    ('"task.xml"', '"melfa"', '[perturbations.p]\nmodel = "approach"\nrotation = -inf', {"CMP012"},
     "-inf is not a finite number"),
    ('"task.xml"', '"melfa"', '[perturbations.p]\nmodel = "object_pose"\nyaw = inf', {"CMP012"}, "not a finite"),
    ('"task.xml"', '"melfa"', "budget = nan", {"CMP012"}, "not a finite number"),
    ('"task.xml"', '"melfa"', '[perturbations."a/b"]\nmodel = "none"', {"CMP027"}, "not a plain name"),
]


@pytest.mark.parametrize("tasks, robots, extra, codes, words", HOSTILE_SPECS)
def test_a_hostile_spec_is_refused_with_its_reason_located(tmp_path: Path, tasks: str, robots: str, extra: str,
                                                           codes: set[str], words: str) -> None:
    _setup_spec(tmp_path)
    spec = tmp_path / "h.toml"
    spec.write_text(SPEC.format(tasks=tasks, robots=robots, extra=extra))
    loaded, found = load_spec(spec)
    errors = [d for d in found if d.severity == "error"]
    found_codes = {d.code for d in errors}
    assert codes <= found_codes and all(c.startswith("ATD") for c in found_codes - codes), found
    assert any(words in d.message for d in errors), [d.message for d in errors]
    assert all(d.loc is not None and d.loc.line >= 1 for d in errors), "every error is located"


def test_a_seeded_mix_of_hostile_edits_is_refused_whole_and_nothing_is_written(tmp_path: Path) -> None:
    """Several hostile edits in one spec: every one is found, in one run, exit 1, and the
    campaign writes nothing (today's spec check ran two of them as a campaign, exit 0)."""
    _setup_spec(tmp_path)
    rng = random.Random(30)
    for round in range(8):
        cases = rng.sample(HOSTILE_SPECS, 3)
        tables = [c for c in cases if c[2].startswith("[")]
        cases = [c for c in cases if not c[2].startswith("[")] + tables[:1]  # a spec has one [perturbations.p]
        extra = "\n".join(sorted((c[2] for c in cases if c[2]), key=lambda e: e.startswith("[")))
        spec = tmp_path / f"mix{round}.toml"
        spec.write_text(SPEC.format(tasks=", ".join(c[0] for c in cases), robots=", ".join(c[1] for c in cases),
                                    extra=extra))
        expected = set().union(*(c[3] for c in cases))
        code, err = _atd("campaign", "run", str(spec), "--store", str(tmp_path / "never.sqlite"))
        assert code == 1, err
        assert expected <= {line.split("error[")[1][:6] for line in err.splitlines() if "error[" in line}, err
        assert not (tmp_path / "never.sqlite").exists()


# --- stores: every damage is one line naming the file, exit 1 --------------------------------

#: Values no campaign writes, by column (an X'..' is a BLOB).
BAD_VALUES = {
    "task": ["X'00'", "''", "'a/b'"], "robot": ["''", "X'ff'"], "index": ["-1", "'x'", "100000", "1.5", "X'01'"],
    "seed": ["-1", "4294967296", "'x'", "2.5"], "status": ["'banana'", "1", "X'6f6b'"], "error": ["5", "X'00'"],
    "sampled": ["'['", "'[1]'", "'{\"dx\": \"far\"}'", "5"], "measurements": ["'{\"lift\": true}'", "X'7b7d'"],
    "events": ["'[1]'", "'{}'", "'nope'"], "task_succeeded": ["2", "-1", "'yes'", "0.5"],
    "judged_succeeded": ["7", "X'01'"], "end_state": ["X'00'", "X''"], "sim_time": ["-1", "'x'", "9e999", "-9e999"],
    "wall_time": ["X'00'", "'soon'"], "summary": ["X'00'"],
}
#: Damage to the store's structure or meta.
BAD_STRUCTURE = [
    "DELETE FROM meta WHERE key = 'spec_text'", "DELETE FROM meta WHERE key = 'created'",
    "UPDATE meta SET value = X'00' WHERE key = 'spec_digest'", "UPDATE meta SET value = 'x1' WHERE key = 'format_version'",
    "UPDATE meta SET value = '../../x' WHERE key = 'campaign'", "UPDATE meta SET value = '[]' WHERE key = 'task_digests'",
    "ALTER TABLE trials DROP COLUMN wall_time", "ALTER TABLE trials ADD COLUMN colour TEXT", "DROP TABLE trials",
    "DROP TABLE meta", "UPDATE trials SET status = 'error' WHERE \"index\" = 1",
    "UPDATE trials SET error = 'boom' WHERE \"index\" = 2",
    # NULL where a campaign never writes one: possible only in a table declared otherwise
    "PRAGMA writable_schema = 1; UPDATE sqlite_master SET sql = replace(sql, 'REAL NOT NULL', 'REAL') "
    "WHERE name = 'trials'",
]


@pytest.fixture(scope="module")
def pristine(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("stores") / "pristine.sqlite"
    with Store.create_or_resume(path, "[campaign]\n", "d1", resume=False) as store:
        for record in preset_records():
            store.add(record)
    return path


def _damaged(pristine: Path, folder: Path, sql: str) -> Path:
    path = folder / "c.sqlite"
    shutil.copy(pristine, path)
    db = sqlite3.connect(path)
    db.executescript(sql)
    db.commit()
    db.close()
    return path


def _refused_in_one_line(path: Path, folder: Path) -> None:
    """The store read and exported: a DamagedStore, and the commands one line, exit 1."""
    with pytest.raises(DamagedStore, match=str(path.name)):
        with Store.open_read(path) as store:
            store.records()
    for command in (["report", str(path)], ["export", str(path), "--format", "json", "-o", str(folder / "x.json")]):
        code, err = _atd("campaign", *command)
        assert code == 1 and err.count("\n") == 1 and str(path) in err and "Traceback" not in err, err
    assert not (folder / "x.json").exists()


def test_a_sample_of_impossible_values_in_a_store_is_refused_naming_the_row(pristine: Path, tmp_path: Path) -> None:
    """Each impossible value was counted (as an error trial, a success, a seed...) or was a traceback."""
    rng = random.Random(30)
    cases = [(column, value) for column, values in BAD_VALUES.items() for value in values]
    for i, (column, value) in enumerate(rng.sample(cases, 24)):
        folder = tmp_path / str(i)
        folder.mkdir()
        row = rng.randint(1, len(preset_records()))
        path = _damaged(pristine, folder, f'UPDATE trials SET "{column}" = {value} WHERE rowid = {row}')
        _refused_in_one_line(path, folder)
        with pytest.raises(DamagedStore, match=f"trial row {row}: {column}") as refused, Store.open_read(path) as store:
            store.records()
        assert not value.startswith("X'") or f"holds {value.upper()} (blob)" in str(refused.value), refused.value


@pytest.mark.parametrize("sql", BAD_STRUCTURE)
def test_a_store_of_another_shape_or_with_broken_meta_is_refused(pristine: Path, tmp_path: Path, sql: str) -> None:
    _refused_in_one_line(_damaged(pristine, tmp_path, sql), tmp_path)


def test_a_store_whose_bytes_are_cut_or_scrambled_never_gives_a_traceback(pristine: Path, tmp_path: Path) -> None:
    """Cut anywhere, or a few bytes overwritten: the store is refused in one line, or (the
    damage within a value that stays valid, or in unused space) read; never anything else."""
    data = pristine.read_bytes()
    rng = random.Random(30)
    refused = 0
    for i in range(40):
        damaged = bytearray(data)
        if i % 2:
            del damaged[rng.randrange(len(data)):]
        else:
            for _ in range(rng.randint(1, 8)):
                damaged[rng.randrange(len(data))] = rng.randrange(256)
        path = tmp_path / f"c{i}.sqlite"
        path.write_bytes(bytes(damaged))
        try:
            with Store.open_read(path) as store:
                store.records()
        except DamagedStore as exc:
            assert str(path) in str(exc) and "\n" not in str(exc)
            refused += 1
    assert refused >= 20, "most damage is where the trials are"


def test_resume_refuses_a_damaged_store_before_any_trial(tmp_path: Path) -> None:
    """Through the command line, in its own process as a user runs it: exit 1, one line, no trial run."""
    shutil.copy(DATA / "claims_success.xml", tmp_path)
    spec = tmp_path / "claims_success.toml"
    shutil.copy(DATA / "claims_success.toml", spec)
    loaded, _ = load_spec(spec)
    path = tmp_path / "c.sqlite"
    cell = Cell("claims_success", "melfa", "main", "mujoco", "robust", "task", "none")
    with Store.create_or_resume(path, loaded.text, loaded.digest, False, loaded.task_digests()) as store:
        store.add(TrialRecord(cell=cell, index=0, seed=1, error="x", status="error"))
    for i, (sql, code) in enumerate((('UPDATE trials SET "index" = -3', 1), ("UPDATE trials SET events = '{'", 1),
                                     ("UPDATE meta SET value = 'x' WHERE key = 'spec_digest'", 2))):
        (tmp_path / str(i)).mkdir()
        damaged = _damaged(path, tmp_path / str(i), sql)
        result = subprocess.run([sys.executable, "-m", "atd", "campaign", "run", str(spec), "--store", str(damaged),
                                 "--resume", "--trials", "2", "-q"], cwd=tmp_path, capture_output=True, text=True,
                                timeout=120)
        assert result.returncode == code and result.stderr.count("\n") == 1, result.stderr
        assert str(damaged) in result.stderr and "Traceback" not in result.stderr
        with sqlite3.connect(damaged) as db:
            assert db.execute("SELECT count(*) FROM trials").fetchone() == (1,), "no trial was run"


# --- two campaigns, one store; an edited task ----------------------------------------------

def test_two_campaigns_making_one_store_at_once_never_share_it(tmp_path: Path) -> None:
    """Both passed the check that the store did not exist, and the second replaced the first's:
    both exited 0 and the store held one campaign's trials. Now one makes it, the other is refused."""
    for round in range(10):
        path = tmp_path / f"c{round}.sqlite"
        start = threading.Barrier(2)
        made, refused = [], []

        def campaign(digest: str) -> None:
            start.wait()
            try:
                store = Store.create_or_resume(path, "[campaign]\n", digest, resume=False)
            except StoreError as exc:
                refused.append(str(exc))
                return
            made.append(digest)
            store.add(preset_records()[0])
            store.close()

        threads = [threading.Thread(target=campaign, args=(d,)) for d in ("first", "second")]
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join()
        assert len(made) == 1 and len(refused) == 1, (made, refused)
        assert "another campaign" in refused[0] or "exists; add --resume" in refused[0]
        with Store.open_read(path) as store:
            assert store.spec_digest == made[0] and len(store.records()) == 1
        assert sorted(p.name for p in tmp_path.iterdir() if p.name.startswith(f".c{round}")) == []


def test_a_store_made_by_another_campaign_in_the_meantime_is_never_replaced(tmp_path: Path, monkeypatch) -> None:
    """The race made certain: the other campaign's store appears just before ours is moved in."""
    path = tmp_path / "c.sqlite"
    link = os.link

    def other_campaign_first(source, target) -> None:
        monkeypatch.undo()  # the other campaign links as campaigns do
        Store.create_or_resume(Path(target), "[campaign]\n", "other", resume=False).close()
        link(source, target)

    monkeypatch.setattr(store_module.os, "link", other_campaign_first)
    with pytest.raises(StoreError, match="was just made by another campaign; give another --store"):
        Store.create_or_resume(path, "[campaign]\n", "mine", resume=False)
    with Store.open_read(path) as store:
        assert store.spec_digest == "other"
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == [], "no temporary file is left"


def test_resume_after_a_task_was_edited_is_refused_naming_the_file(tmp_path: Path) -> None:
    (tmp_path / "task.xml").write_text(TASK)
    spec = tmp_path / "h.toml"
    spec.write_text(SPEC.format(tasks='"task.xml"', robots='"melfa"', extra=""))
    loaded, _ = load_spec(spec)
    path = tmp_path / "h.sqlite"
    Store.create_or_resume(path, loaded.text, loaded.digest, False, loaded.task_digests()).close()
    (tmp_path / "task.xml").write_text(TASK.replace("<timeout>1</timeout>", "<timeout>2</timeout>"))
    code, err = _atd("campaign", "run", str(spec), "--store", str(path), "--resume", "-q")
    assert code == 2 and err.count("\n") == 1, err
    assert "task.xml (relative to the spec) has changed since" in err and "mix trials of both versions" in err


# --- outputs checked before the first trial; a huge spec starts at once -------------------------

def test_recordings_that_could_not_be_written_are_refused_before_anything_is_written(tmp_path: Path) -> None:
    long = "t" * 230  # a task name that makes each recording's name over 255 bytes
    (tmp_path / f"{long}.xml").write_text(TASK)
    spec = tmp_path / "h.toml"
    spec.write_text(SPEC.format(tasks=f'"{long}.xml"', robots='"melfa"', extra=""))
    folder = tmp_path / "recordings"
    folder.mkdir()
    store = tmp_path / "h.sqlite"
    for recordings, words in ((folder, "over the 255 a file name may have"), (tmp_path / "nowhere", "no such folder")):
        code, err = _atd("campaign", "run", str(spec), "--store", str(store), "--record-failed", str(recordings))
        assert code == 2 and err.count("\n") == 1 and words in err, err
    assert not store.exists() and list(folder.iterdir()) == []


def test_a_recording_name_taken_by_a_folder_is_refused_before_anything_is_written(tmp_path: Path,
                                                                                 monkeypatch) -> None:
    monkeypatch.setattr("atd.cli.campaign_run.new_campaign_id", lambda: "0badcafe")
    spec = tmp_path / "claims_success.toml"
    shutil.copy(DATA / "claims_success.toml", spec)
    shutil.copy(DATA / "claims_success.xml", tmp_path)
    folder = tmp_path / "recordings"
    (folder / "claims_success-0badcafe__claims_success__melfa__main__mujoco__robust__task__none__0.mcap").mkdir(
        parents=True)
    code, err = _atd("campaign", "run", str(spec), "--store", str(tmp_path / "c.sqlite"), "--record-failed",
                     str(folder))
    assert code == 2 and "not a regular file" in err, err
    assert not (tmp_path / "c.sqlite").exists()


def test_a_spec_of_millions_of_trials_makes_its_plans_as_they_are_taken(tmp_path: Path) -> None:
    """100,000 trials in each of 72 cells: every plan was made before the first trial (no
    trial after 90 s, 411 MB); now the first is made at once, the same as it ever was."""
    spec = tmp_path / "big.toml"
    shutil.copy(DATA / "claims_success.xml", tmp_path / "task.xml")
    spec.write_text(SPEC.format(tasks='"task.xml"', robots='"melfa", "tombatossals", "baxter"',
                                extra='trials = 100000\nengines = ["mujoco", "pybullet"]\ngrasps = ["naive", "robust"]\n'
                                      'objects = ["task", "mug", "duck"]\n[perturbations.none]\nmodel = "none"\n'
                                      '[perturbations.approach]\nmodel = "approach"').replace("trials = 1\n", ""))
    loaded, found = load_spec(spec)
    assert loaded is not None, found
    started = time.perf_counter()
    chosen = plans(loaded)
    asked: list[str] = []
    todo = chosen.skipping(lambda cell: asked.append(cell.key) or {0, 2})
    first, second = next(todo), next(todo)
    assert time.perf_counter() - started < 1.0
    assert len(chosen) == 72 * 100_000 and len(asked) == 1, "a cell's stored trials are asked for when it is reached"
    cell = chosen.cells[0][0]
    assert (first.index, second.index) == (1, 3)
    assert first.seed == trial_seed(loaded.spec.base_seed, cell, 1) and second.cell == cell
