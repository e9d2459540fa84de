"""The campaign store: one SQLite file holding the spec it was made from, the digests of its
tasks and one row per finished trial. Each row is committed as its trial ends, so a killed
campaign loses only the trials in flight and `--resume` knows what is left. Only the
campaign's parent process writes; reports open it read-only.

Opening a store checks it whole before anything is read from it: its tables as this atd
makes them, its meta complete, every row's values of the types and ranges a campaign
writes (in SQL, so a store of millions of trials is checked in seconds). A damaged store is
then one line naming the file, the row and the value, not a traceback or a wrong count.
"""

from __future__ import annotations

import fcntl
import json
import os
import re
import secrets
import sqlite3
import tempfile
from contextlib import contextmanager
from dataclasses import dataclass
from datetime import datetime, timezone
from functools import cache
from pathlib import Path
from types import TracebackType
from typing import Any, Iterator, Mapping

from atd.campaign.record import DIMENSIONS, Cell, TrialRecord
from atd.model import ranges
from atd.model.files import describe_write_error, output_problem

#: Bumped when a column's meaning changes; a store of a newer format is refused, not misread.
FORMAT_VERSION = 1
#: Every store has these meta keys. Stores made before atd keyed them to their tasks lack
#: `task_digests` and `campaign` (the id that names their recordings); a resume adds them.
_META_KEYS = ("format_version", "spec_text", "spec_digest", "created")
CAMPAIGN_ID = re.compile(r"[0-9a-f]{8}")


@dataclass(frozen=True)
class _Column:
    """A trial column: its declaration, and what every value a campaign writes there is, in
    SQL (`{c}` is the column) and in words."""

    name: str
    kind: str
    valid: str
    expected: str


def _quoted(column: str) -> str:
    """A column's name in SQL: `index` is a keyword, and a name in single quotes is a string."""
    return f'"{column}"'


_NAME = ("typeof({c}) = 'text' AND {c} != '' AND instr({c}, '/') = 0", "where a campaign writes a name (text, no '/')")
_TEXT = ("typeof({c}) = 'text'", "where a campaign writes text")  # JSON too: its JSON is checked as it is read
_FLAG = ("typeof({c}) = 'integer' AND {c} IN (0, 1)", "where a campaign writes 0 or 1")
_SECONDS = ("typeof({c}) IN ('integer', 'real') AND {c} >= 0 AND {c} < 1e300",
            "where a campaign writes seconds, finite and not negative")
_LAST_INDEX = int(ranges.TRIALS.high) - 1

#: The trial columns in `TrialRecord.as_dict` terms; JSON columns hold the dicts and lists.
_COLUMNS: tuple[_Column, ...] = (
    *(_Column(d, "TEXT NOT NULL", *_NAME) for d in DIMENSIONS),
    _Column("index", "INTEGER NOT NULL", f"typeof({{c}}) = 'integer' AND {{c}} BETWEEN 0 AND {_LAST_INDEX}",
            f"where a campaign writes a trial number from 0 to {_LAST_INDEX}"),
    _Column("seed", "INTEGER NOT NULL", f"typeof({{c}}) = 'integer' AND {{c}} BETWEEN 0 AND {int(ranges.SEED.high)}",
            "where a campaign writes a 32-bit seed"),
    _Column("status", "TEXT NOT NULL", "typeof({c}) = 'text' AND {c} IN ('ok', 'error')",
            "where a campaign writes 'ok' or 'error'"),
    _Column("error", "TEXT NOT NULL", *_TEXT),
    _Column("sampled", "TEXT NOT NULL", *_TEXT),
    _Column("task_succeeded", "INTEGER NOT NULL", *_FLAG),
    _Column("end_state", "TEXT", "typeof({c}) IN ('text', 'null')", "where a campaign writes text or NULL"),
    _Column("summary", "TEXT NOT NULL", *_TEXT),
    _Column("events", "TEXT NOT NULL", *_TEXT),
    _Column("judged_succeeded", "INTEGER NOT NULL", *_FLAG),
    _Column("judge_reason", "TEXT NOT NULL", *_TEXT),
    _Column("measurements", "TEXT NOT NULL", *_TEXT),
    _Column("sim_time", "REAL NOT NULL", *_SECONDS),
    _Column("wall_time", "REAL NOT NULL", *_SECONDS),
    _Column("setup_time", "REAL NOT NULL", *_SECONDS),
)
#: What a whole row must be: (the column to show, the check in SQL, what is wrong in words).
_ROW_CHECKS: tuple[tuple[str, str, str], ...] = (
    *((c.name, c.valid.format(c=_quoted(c.name)), c.expected) for c in _COLUMNS),
    ("error", "status = 'ok' OR error != ''", "but its status is 'error', which always says what went wrong"),
    ("error", "status = 'error' OR error = ''", "but its status is 'ok': a trial that ran has no error"),
)
#: The JSON columns, and what each holds.
_JSON_COLUMNS = {"sampled": "an object of numbers", "measurements": "an object of numbers",
                 "events": "a list of objects"}
_BOOL_COLUMNS = frozenset({"task_succeeded", "judged_succeeded"})
_NAMES = ", ".join(_quoted(c.name) for c in _COLUMNS)
_CELL_NAMES = ", ".join(map(_quoted, DIMENSIONS))
_OF_CELL = " AND ".join(f"{_quoted(d)} = ?" for d in DIMENSIONS)

_SCHEMA = f"""
CREATE TABLE meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE trials (
  {", ".join(f"{_quoted(c.name)} {c.kind}" for c in _COLUMNS)},
  PRIMARY KEY ({_CELL_NAMES}, "index")
);
"""


class StoreError(Exception):
    """A store that cannot be used as asked; the message is for the user, one line."""


class DamagedStore(StoreError):
    """A file that is not a campaign store, or one whose content no campaign writes."""


def new_campaign_id() -> str:
    """A fresh campaign's id: its recordings' names carry it, so no two campaigns' collide."""
    return secrets.token_hex(4)


class Store:
    """An open campaign store. Use it as a context manager, from one thread at a time."""

    def __init__(self, path: Path, db: sqlite3.Connection, meta: dict[str, str]) -> None:
        self.path = path
        self._db = db
        self._lock: int | None = None  # a writer's exclusive lock on the file (`_take_lock`)
        self.keyed_now = False  # this resume gave task digests to a store made without them
        self.spec_text: str = meta["spec_text"]
        self.spec_digest: str = meta["spec_digest"]
        self.created: str = meta["created"]
        self.campaign: str | None = meta.get("campaign")
        self.task_digests: dict[str, str] | None = json.loads(meta["task_digests"]) if "task_digests" in meta else None

    @classmethod
    def create_or_resume(cls, path: Path, spec_text: str, spec_digest: str, resume: bool,
                         tasks: Mapping[str, str] | None = None, campaign: str | None = None) -> Store:
        """A new store at `path`, or with `resume` the existing one made from the same spec and
        tasks (a missing store is then started afresh). `tasks` are the digests of the files the
        tasks are made of; `campaign` the id of a new store (default: a fresh one)."""
        path = Path(path)
        tasks = dict(tasks or {})
        problem = output_problem(path)
        if problem:
            raise StoreError(f"{path}: {problem}")
        if not path.exists():
            try:
                return cls._create(path, spec_text, spec_digest, tasks, campaign or new_campaign_id())
            except FileExistsError:  # another campaign made it in the meantime; it is never replaced
                if not resume:
                    raise StoreError(f"{path} was just made by another campaign; give another --store") from None
        elif not resume:
            raise StoreError(f"{path} exists; add --resume to continue it, or give another --store")
        store = cls._open(path, read_only=False)
        try:
            store._take_lock()
            store._check_made_from(spec_digest, tasks)
            for _ in store.each():  # every row's JSON too, before any trial is added to them
                pass
            store._complete(tasks, campaign or new_campaign_id())
        except BaseException:
            store.close()
            raise
        return store

    def _check_made_from(self, spec_digest: str, tasks: dict[str, str]) -> None:
        """Resume only what would give the same trials: the same spec and the same tasks."""
        if self.spec_digest != spec_digest:
            raise StoreError(f"{self.path} was made from a different spec; give another --store, "
                             f"or run the spec it was made from")
        if self.task_digests is None:
            return
        changed = sorted(f for f in self.task_digests.keys() | tasks.keys()
                         if self.task_digests.get(f) != tasks.get(f))
        if changed:
            more = f" (and {len(changed) - 1} more)" if len(changed) > 1 else ""
            raise StoreError(f"{self.path} was made from other task content: {changed[0]} (relative to the spec)"
                             f"{more} has changed since; --resume would mix trials of both versions: give another "
                             f"--store, or restore the file as it was")

    def _complete(self, tasks: dict[str, str], campaign: str) -> None:
        """Give a store made before atd kept them its task digests and a campaign id."""
        missing = {}
        if self.task_digests is None:
            missing["task_digests"] = json.dumps(tasks)
        if self.campaign is None:
            missing["campaign"] = campaign
        if not missing:
            return
        try:
            with self._db:
                self._db.executemany("INSERT INTO meta VALUES (?, ?)", missing.items())
        except sqlite3.Error as exc:
            raise _write_failed(self.path, exc) from None
        self.keyed_now = self.task_digests is None
        self.task_digests = tasks if self.task_digests is None else self.task_digests
        self.campaign = self.campaign or campaign

    def _take_lock(self) -> None:
        """One campaign writes a store at a time: a second one started on it (a resume in
        another terminal) would run the same trials again and stop on the first it stores."""
        self._lock = os.open(self.path, os.O_RDONLY)
        try:
            fcntl.flock(self._lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise StoreError(f"{self.path} is being written by another campaign; wait for it to end, "
                             f"or give another --store") from None

    @classmethod
    def open_read(cls, path: Path) -> Store:
        """An existing store, opened read-only for reports and exports."""
        path = Path(path)
        if not path.exists():
            raise DamagedStore(f"{path}: no such file; give the --store file a campaign wrote")
        if not path.is_file():
            raise DamagedStore(f"{path} is not a regular file; give the --store file a campaign wrote")
        return cls._open(path, read_only=True)

    @classmethod
    def _create(cls, path: Path, spec_text: str, spec_digest: str, tasks: dict[str, str], campaign: str) -> Store:
        """Build the empty store under a temporary name, locked, and link it into place only
        if nothing is there: a crash never leaves a store without its spec, and of two
        campaigns making the same store at once, the second gets FileExistsError."""
        meta = {
            "format_version": str(FORMAT_VERSION),
            "spec_text": spec_text,
            "spec_digest": spec_digest,
            "created": datetime.now(timezone.utc).isoformat(timespec="seconds"),
            "task_digests": json.dumps(tasks),
            "campaign": campaign,
        }
        try:
            lock, tmp = tempfile.mkstemp(prefix=f".{path.name[:32]}.", suffix=".tmp", dir=path.parent)
            try:
                fcntl.flock(lock, fcntl.LOCK_EX)  # held from birth: no campaign can take the store before us
                db = sqlite3.connect(tmp)
                try:
                    db.executescript(_SCHEMA)
                    with db:
                        db.executemany("INSERT INTO meta VALUES (?, ?)", meta.items())
                    db.execute("PRAGMA journal_mode=WAL")
                finally:
                    db.close()
                os.chmod(tmp, 0o644)
                os.link(tmp, path)  # never replaces: FileExistsError
            except BaseException:
                os.close(lock)
                raise
            finally:
                os.unlink(tmp)
        except FileExistsError:
            raise
        except OSError as exc:
            raise StoreError(describe_write_error(path, exc)) from None
        except sqlite3.Error as exc:
            raise _write_failed(path, exc) from None
        try:
            db = _connect(path, read_only=False)
            db.execute("SELECT count(*) FROM meta").fetchone()  # the first read makes the -shm file: a write
        except (StoreError, sqlite3.Error) as exc:
            os.close(lock)
            for made in (path, Path(f"{path}-wal"), Path(f"{path}-shm")):
                made.unlink(missing_ok=True)
            raise _write_failed(path, exc) from None
        store = cls(path, db, meta)
        store._lock = lock
        return store

    @classmethod
    def _open(cls, path: Path, read_only: bool) -> Store:
        db = _connect(path, read_only)
        try:
            meta = _checked(db, path)
        except BaseException:
            db.close()
            raise
        return cls(path, db, meta)

    def add(self, record: TrialRecord) -> None:
        """Commit one finished trial; it survives whatever happens to the campaign next."""
        data = record.as_dict()
        values = [json.dumps(data[c.name]) if c.name in _JSON_COLUMNS else data[c.name] for c in _COLUMNS]
        try:
            with self._db:
                self._db.execute(f"INSERT INTO trials ({_NAMES}) VALUES ({', '.join('?' * len(_COLUMNS))})",
                                 values)
        except sqlite3.IntegrityError:
            raise StoreError(f"{self.path}: trial {record.index} of cell {record.cell.key} "
                             f"is already stored") from None
        except sqlite3.Error as exc:
            raise _write_failed(self.path, exc) from None

    def counts(self, below: int) -> dict[str, int]:
        """How many trials numbered below `below` are stored, by cell key (errors count: they ran)."""
        with self._reading():
            rows = self._db.execute(f'SELECT {_CELL_NAMES}, count(*) FROM trials WHERE "index" < ? '
                                    f"GROUP BY {_CELL_NAMES}", (below,)).fetchall()
        return {Cell(*row[:-1]).key: row[-1] for row in rows}

    def indices(self, cell: Cell, below: int) -> set[int]:
        """The numbers, below `below`, of the cell's stored trials."""
        values = [getattr(cell, d) for d in DIMENSIONS]
        with self._reading():
            rows = self._db.execute(f'SELECT "index" FROM trials WHERE {_OF_CELL} AND "index" < ?', (*values, below))
            return {row[0] for row in rows}

    def each(self) -> Iterator[TrialRecord]:
        """Every stored trial, in no set order, one at a time: a store of millions is never all
        in memory. StoreError names the row a damaged file cannot give back."""
        with self._reading():
            for rowid, *row in self._db.execute(f"SELECT rowid, {_NAMES} FROM trials"):
                try:
                    yield TrialRecord.from_dict(_decode(row))
                except ValueError as exc:
                    raise DamagedStore(f"{self.path}: trial row {rowid}: {exc}; the store is damaged") from None

    def records(self) -> list[TrialRecord]:
        """Every stored trial, ordered by cell key then trial index."""
        return sorted(self.each(), key=lambda r: (r.cell.key, r.index))

    @contextmanager
    def _reading(self) -> Iterator[None]:
        """SQLite's errors and text that is not UTF-8 as one StoreError: the file is damaged."""
        try:
            yield
        except (sqlite3.Error, UnicodeDecodeError) as exc:
            raise DamagedStore(f"{self.path}: a stored trial cannot be read ({exc}); the store is damaged") from None

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


def _connect(path: Path, read_only: bool) -> sqlite3.Connection:
    uri = f"{path.resolve().as_uri()}?mode={'ro' if read_only else 'rw'}"
    try:
        return sqlite3.connect(uri, uri=True, check_same_thread=False)
    except sqlite3.Error as exc:
        raise StoreError(f"{path}: cannot open ({exc}); check its permissions") from None


def _checked(db: sqlite3.Connection, path: Path) -> dict[str, str]:
    """The store's meta, once its tables, meta and every row are what a campaign writes."""
    fix = "give the --store file a campaign wrote"
    try:
        tables = {name: db.execute(f"PRAGMA table_info({name})").fetchall() for name in _tables()}
    except sqlite3.DatabaseError as exc:  # not SQLite, or its first pages cut off
        raise DamagedStore(f"{path} is not a campaign store ({exc}); {fix}") from None
    try:
        for name, expected in _tables().items():
            if tables[name] != expected:
                raise DamagedStore(f"{path} is not a campaign store "
                                   f"({_table_difference(name, tables[name], expected)}); {fix}")
        meta = _meta(db, path)
        _check_rows(db, path)
    except (sqlite3.Error, UnicodeDecodeError) as exc:
        raise DamagedStore(f"{path} cannot be read ({exc}); the store is damaged") from None
    return meta


@cache
def _tables() -> dict[str, list[tuple]]:
    """What `PRAGMA table_info` says of each table of a store this atd makes."""
    db = sqlite3.connect(":memory:")
    try:
        db.executescript(_SCHEMA)
        return {name: db.execute(f"PRAGMA table_info({name})").fetchall() for name in ("meta", "trials")}
    finally:
        db.close()


def _table_difference(name: str, found: list[tuple], expected: list[tuple]) -> str:
    """The first way a table differs from this atd's, in words."""
    if not found:
        return f"it has no {name} table"
    have = {row[1]: row for row in found}
    for row in expected:
        if row[1] not in have:
            return f"its {name} table has no column '{row[1]}'"
        if have[row[1]][2:] != row[2:]:
            return f"its {name} table declares '{row[1]}' otherwise"
    extra = next(row[1] for row in found if row[1] not in {r[1] for r in expected})
    return f"its {name} table has a column '{extra}' that atd does not write"


def _meta(db: sqlite3.Connection, path: Path) -> dict[str, str]:
    damaged = f"{path}: the store is damaged"
    rows = db.execute("SELECT key, value, typeof(value) FROM meta").fetchall()
    meta = {key: value for key, value, kind in rows if kind == "text"}
    missing = next((k for k in _META_KEYS if k not in meta), None)
    if missing:
        raise DamagedStore(f"{damaged}: its meta has no text '{missing}'")
    version = meta["format_version"]
    if not re.fullmatch(r"[0-9]{1,9}", version):
        raise DamagedStore(f"{damaged}: its format_version '{version[:20]}' is not a number")
    if int(version) > FORMAT_VERSION:
        raise StoreError(f"{path} has store format {version}, newer than this atd reads "
                         f"({FORMAT_VERSION}); upgrade atd")
    if "campaign" in meta and not CAMPAIGN_ID.fullmatch(meta["campaign"]):
        raise DamagedStore(f"{damaged}: its campaign id '{meta['campaign'][:20]}' is not 8 hex digits")
    if "task_digests" in meta:
        try:
            digests = json.loads(meta["task_digests"])
        except ValueError:
            digests = None
        if not isinstance(digests, dict) or not all(isinstance(v, str) for v in digests.values()):
            raise DamagedStore(f"{damaged}: its task_digests are not a JSON object of digests")
    return meta


def _check_rows(db: sqlite3.Connection, path: Path) -> None:
    """DamagedStore naming the first row with a value no campaign writes, and the value
    (in one query: a damaged file may not find the row again by its rowid)."""
    def by_problem(value: str) -> str:
        whens = (f"WHEN {i} THEN {value.format(c=_quoted(column))}" for i, (column, _, _) in enumerate(_ROW_CHECKS))
        return f"CASE problem {' '.join(whens)} END"

    problem = " ".join(f"WHEN ({sql}) IS NOT 1 THEN {i}" for i, (_, sql, _) in enumerate(_ROW_CHECKS))
    found = db.execute(f"SELECT rowid, problem, {by_problem('typeof({c})')}, "
                       f"{by_problem('CAST(substr(quote({c}), 1, 60) AS BLOB)')} "
                       f"FROM (SELECT rowid, *, CASE {problem} END AS problem FROM trials) "
                       "WHERE problem IS NOT NULL LIMIT 1").fetchone()
    if found is None:
        return
    rowid, number, kind, shown = found
    column, _, expected = _ROW_CHECKS[number]
    raise DamagedStore(f"{path}: trial row {rowid}: {column} holds {shown.decode('utf-8', 'replace')} ({kind}) "
                       f"{expected}; the store is damaged")


def _decode(row: list[Any]) -> dict[str, Any]:
    """A row as `TrialRecord.from_dict` takes it; ValueError for JSON that is not what a
    campaign writes (SQL has checked every other column)."""
    data: dict[str, Any] = {}
    for column, value in zip(_COLUMNS, row):
        if column.name in _JSON_COLUMNS:
            try:
                value = json.loads(value)
            except ValueError as exc:
                raise ValueError(f"{column.name} is not JSON ({exc})") from None
            if not _shaped(column.name, value):
                raise ValueError(f"{column.name} is not {_JSON_COLUMNS[column.name]}")
        elif column.name in _BOOL_COLUMNS:
            value = bool(value)
        data[column.name] = value
    return data


def _shaped(column: str, value: Any) -> bool:
    if column == "events":
        return isinstance(value, list) and all(isinstance(event, dict) for event in value)
    return isinstance(value, dict) and all(isinstance(v, (int, float)) and not isinstance(v, bool)
                                           for v in value.values())


def _write_failed(path: Path, exc: Exception) -> StoreError:
    """SQLite's word for a failed write ("disk I/O error", "database or disk is full") does not
    say what to do; the usual causes do."""
    return StoreError(f"cannot write {path}: {exc} (a full disk, a file-size limit or no permission); "
                      "free some space or write elsewhere")
