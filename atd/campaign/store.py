"""The campaign store: one SQLite file holding the spec it was made from and one row per
finished trial. Each row is committed as its trial ends, so a killed campaign loses only
the trials in flight and `--resume` knows what is left. Only the campaign's parent
process writes; reports open it read-only.
"""

from __future__ import annotations

import fcntl
import json
import os
import sqlite3
from datetime import datetime, timezone
from pathlib import Path
from types import TracebackType
from typing import Any

from atd.campaign.record import DIMENSIONS, Cell, TrialRecord
from atd.model import replacing
from atd.model.files import describe_write_error, output_problem

#: Bumped when a column's meaning changes; a store of a newer format is refused, not misread.
FORMAT_VERSION = 1

#: The trial columns in `TrialRecord.as_dict` terms; JSON columns hold the dicts and lists.
_COLUMNS: tuple[tuple[str, str], ...] = (
    *((d, "TEXT NOT NULL") for d in DIMENSIONS),
    ("index", "INTEGER NOT NULL"),
    ("seed", "INTEGER NOT NULL"),
    ("status", "TEXT NOT NULL"),
    ("error", "TEXT NOT NULL"),
    ("sampled", "TEXT NOT NULL"),
    ("task_succeeded", "INTEGER NOT NULL"),
    ("end_state", "TEXT"),
    ("summary", "TEXT NOT NULL"),
    ("events", "TEXT NOT NULL"),
    ("judged_succeeded", "INTEGER NOT NULL"),
    ("judge_reason", "TEXT NOT NULL"),
    ("measurements", "TEXT NOT NULL"),
    ("sim_time", "REAL NOT NULL"),
    ("wall_time", "REAL NOT NULL"),
    ("setup_time", "REAL NOT NULL"),
)
_JSON_COLUMNS = frozenset({"sampled", "events", "measurements"})
_BOOL_COLUMNS = frozenset({"task_succeeded", "judged_succeeded"})
_NAMES = ", ".join(f'"{name}"' for name, _ in _COLUMNS)
_CELL_NAMES = ", ".join(f'"{d}"' for d in DIMENSIONS)

_SCHEMA = f"""
CREATE TABLE meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE trials (
  {", ".join(f'"{name}" {kind}' for name, kind in _COLUMNS)},
  PRIMARY KEY ({_CELL_NAMES}, "index")
);
"""


class StoreError(Exception):
    """A store that cannot be used as asked; the message is for the user, one line."""


class Store:
    """An open campaign store. Use it as a context manager, from one thread at a time."""

    def __init__(self, path: Path, db: sqlite3.Connection) -> None:
        self.path = path
        self._db = db
        self._lock: int | None = None  # a writer's exclusive lock on the file (`_take_lock`)
        meta = dict(db.execute("SELECT key, value FROM meta"))
        self.spec_text: str = meta["spec_text"]
        self.spec_digest: str = meta["spec_digest"]
        self.created: str = meta["created"]

    @classmethod
    def create_or_resume(cls, path: Path, spec_text: str, spec_digest: str, resume: bool) -> Store:
        """A new store at `path`, or with `resume` the existing one made from the same spec
        (a missing store is then started afresh)."""
        path = Path(path)
        problem = output_problem(path)
        if problem:
            raise StoreError(f"{path}: {problem}")
        if path.exists():
            if not resume:
                raise StoreError(f"{path} exists; add --resume to continue it, or give another --store")
            store = cls._open(path, read_only=False)
            if store.spec_digest != spec_digest:
                store.close()
                raise StoreError(f"{path} was made from a different spec; give another --store, "
                                 f"or run the spec it was made from")
        else:
            cls._build(path, spec_text, spec_digest)
            store = cls._open(path, read_only=False)
        store._take_lock()
        return store

    def _take_lock(self) -> None:
        """One campaign writes a store at a time: a second one started on it (a resume in
        another terminal) would run the same trials again and stop on the first it stores."""
        self._lock = os.open(self.path, os.O_RDONLY)
        try:
            fcntl.flock(self._lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            self.close()
            raise StoreError(f"{self.path} is being written by another campaign; wait for it to end, "
                             f"or give another --store") from None

    @classmethod
    def open_read(cls, path: Path) -> Store:
        """An existing store, opened read-only for reports and exports."""
        path = Path(path)
        if not path.exists():
            raise StoreError(f"{path}: no such file; give the --store file a campaign wrote")
        if not path.is_file():
            raise StoreError(f"{path} is not a regular file; give the --store file a campaign wrote")
        return cls._open(path, read_only=True)

    @staticmethod
    def _build(path: Path, spec_text: str, spec_digest: str) -> None:
        """Write the empty store beside `path` and move it in whole: a crash while it is
        being made never leaves a file that `--resume` would refuse."""
        meta = {
            "format_version": str(FORMAT_VERSION),
            "spec_text": spec_text,
            "spec_digest": spec_digest,
            "created": datetime.now(timezone.utc).isoformat(timespec="seconds"),
        }
        try:
            with replacing(path) as tmp:
                db = sqlite3.connect(tmp)
                try:
                    db.executescript(_SCHEMA)
                    with db:
                        db.executemany("INSERT INTO meta VALUES (?, ?)", meta.items())
                    db.execute("PRAGMA journal_mode=WAL")
                finally:
                    db.close()
        except OSError as exc:
            raise StoreError(describe_write_error(path, exc)) from None
        except sqlite3.OperationalError as exc:
            raise _write_failed(path, exc) from None

    @classmethod
    def _open(cls, path: Path, read_only: bool) -> Store:
        uri = f"{path.resolve().as_uri()}?mode={'ro' if read_only else 'rw'}"
        try:
            db = sqlite3.connect(uri, uri=True, check_same_thread=False)
        except sqlite3.Error as exc:
            raise StoreError(f"{path}: cannot open ({exc}); check its permissions") from None
        try:
            version = cls._format_version(db, path)
        except BaseException:
            db.close()
            raise
        if version > FORMAT_VERSION:
            db.close()
            raise StoreError(f"{path} has store format {version}, newer than this atd reads "
                             f"({FORMAT_VERSION}); upgrade atd")
        return cls(path, db)

    @staticmethod
    def _format_version(db: sqlite3.Connection, path: Path) -> int:
        not_a_store = f"{path} is not a campaign store; give the --store file a campaign wrote"
        try:
            row = db.execute("SELECT value FROM meta WHERE key = 'format_version'").fetchone()
            db.execute("SELECT count(*) FROM trials").fetchone()
        except (sqlite3.DatabaseError, ValueError):  # ValueError: text a damaged file does not decode
            raise StoreError(not_a_store) from None
        if row is None or not str(row[0]).isdigit():
            raise StoreError(not_a_store)
        return int(row[0])

    def add(self, record: TrialRecord) -> None:
        """Commit one finished trial; it survives whatever happens to the campaign next."""
        data = record.as_dict()
        values = [json.dumps(data[name]) if name in _JSON_COLUMNS else data[name] for name, _ in _COLUMNS]
        try:
            with self._db:
                self._db.execute(f"INSERT INTO trials ({_NAMES}) VALUES ({', '.join('?' * len(_COLUMNS))})",
                                 values)
        except sqlite3.IntegrityError:
            raise StoreError(f"{self.path}: trial {record.index} of cell {record.cell.key} "
                             f"is already stored") from None
        except sqlite3.OperationalError as exc:
            raise _write_failed(self.path, exc) from None

    def done(self) -> set[tuple[str, int]]:
        """(cell key, trial index) of every stored trial, errors included: they ran."""
        rows = self._db.execute(f'SELECT {_CELL_NAMES}, "index" FROM trials')
        return {(Cell(*row[:-1]).key, row[-1]) for row in rows}

    def records(self) -> list[TrialRecord]:
        """Every stored trial, ordered by cell key then trial index; StoreError when a row of a
        damaged file cannot be read back."""
        try:
            found = [TrialRecord.from_dict(self._decode(row)) for row in self._db.execute(
                f"SELECT {_NAMES} FROM trials")]
        except Exception as exc:  # noqa: BLE001 - SQLite, UTF-8, JSON or a field: the file is damaged either way
            raise StoreError(f"{self.path}: a stored trial cannot be read ({exc}); the store is damaged") from None
        return sorted(found, key=lambda r: (r.cell.key, r.index))

    @staticmethod
    def _decode(row: tuple[Any, ...]) -> dict[str, Any]:
        data: dict[str, Any] = {}
        for (name, _), value in zip(_COLUMNS, row):
            if name in _JSON_COLUMNS:
                value = json.loads(value)
            elif name in _BOOL_COLUMNS:
                value = bool(value)
            data[name] = value
        return data

    def close(self) -> None:
        self._db.close()
        if self._lock is not None:
            os.close(self._lock)  # and with it the lock
            self._lock = None

    def __enter__(self) -> Store:
        return self

    def __exit__(self, kind: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        self.close()


def _write_failed(path: Path, exc: sqlite3.OperationalError) -> StoreError:
    """SQLite's word for a failed write ("disk I/O error", "database or disk is full") does not
    say what to do; the usual causes do."""
    return StoreError(f"cannot write {path}: {exc} (a full disk, a file-size limit or no permission); "
                      "free some space or write elsewhere")
