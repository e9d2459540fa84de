"""`atd campaign run`: run a campaign spec's trials into a store."""

from __future__ import annotations

import os
import signal
from collections import Counter
from contextlib import contextmanager
from dataclasses import replace
from importlib.util import find_spec
from pathlib import Path
from typing import Iterator

import click

from atd.campaign.cells import Plans, parse_only, plans
from atd.campaign.progress import Progress
from atd.campaign.record import TrialRecord
from atd.campaign.runner import RayError, WorkerError, ray_joined, run_local, run_ray
from atd.campaign.spec import LoadedSpec, load_spec
from atd.campaign.store import DamagedStore, Store, StoreError, new_campaign_id
from atd.cli.app import EXIT_INVALID, EXIT_USAGE, OutputFile, Ranged, campaign, guard_outputs
from atd.model import has_errors, ranges
from atd.model.diagnostics import render_all
from atd.model.files import real_path

EXIT_INTERRUPTED = 130  # the shell's code for a command stopped by Ctrl-C


def _fail(message: str, code: int) -> None:
    click.echo(message, err=True)
    raise SystemExit(code)


def _stop(signum: int, frame: object) -> None:
    raise KeyboardInterrupt


@campaign.command("run")
@click.argument("spec_file", metavar="SPEC.toml", type=click.Path(path_type=Path))  # read by the input guard
@click.option("--workers", "-j", type=Ranged(ranges.WORKERS, integer=True), default=None,
              help="worker processes (default: every core)")
@click.option("--ray", "ray_address", is_flag=False, flag_value="", default=None, metavar="[ADDRESS]",
              help="run the trials on Ray: a local instance, or the cluster at ADDRESS")
@click.option("--store", "store_path", type=OutputFile(), default=None,
              help="the SQLite store (default: NAME.sqlite in the current folder, NAME from the spec)")
@click.option("--resume", is_flag=True, help="continue a stopped campaign: run only the trials the store lacks")
@click.option("--only", multiple=True, metavar="DIMENSION=VALUE",
              help="run only the cells with this value (repeatable; task, robot, arm, engine, grasp, object, "
                   "perturbation)")
@click.option("--trials", type=Ranged(ranges.TRIALS, integer=True), default=None, help="run only the first N trials of each cell")
@click.option("--record-failed", type=click.Path(path_type=Path, file_okay=False), default=None, metavar="DIR",
              help="record every trial the judge fails as MCAP into DIR (see atd report)")
@click.option("--quiet", "-q", is_flag=True, help="no progress display")
def run_campaign(spec_file: Path, workers: int | None, ray_address: str | None, store_path: Path | None,
                 resume: bool, only: tuple[str, ...], trials: int | None, record_failed: Path | None,
                 quiet: bool) -> None:
    """Run the trials of SPEC.toml, each judged by the simulator's ground truth, into a store.

    Every trial's record is committed as it ends, so a stopped campaign (Ctrl-C or SIGTERM
    stop it cleanly; a crash) loses only the trials in flight; --resume continues it. Seeds depend only on the spec,
    so the records do not depend on --workers, --ray or the order trials ran in.
    """
    if ray_address is not None and find_spec("ray") is None:
        _fail("error: --ray needs Ray, which is not installed; pip install 'atd-robotics[ray]'", EXIT_USAGE)
    loaded, found = load_spec(spec_file)
    if loaded is None or has_errors(found):
        _fail(render_all(found), EXIT_INVALID)
    campaign_id = new_campaign_id()  # a resumed store keeps its own, as long
    chosen = _chosen(loaded, spec_file, only, trials, record_failed, campaign_id)
    store_path = store_path or Path.cwd() / f"{loaded.spec.name}.sqlite"
    guard_outputs({"--store": store_path}, [loaded.task_path(entry) for entry in loaded.spec.task_entries])
    tasks = loaded.task_digests()
    workers = workers or os.cpu_count() or 1
    with _ray(ray_address, workers), _open_store(store_path, loaded, resume, tasks, campaign_id) as store:
        chosen = replace(chosen, campaign=f"{loaded.spec.name}-{store.campaign}")
        lost = _run(chosen, store, spec_file.name, workers, ray_address, quiet)
        tally = _tally(chosen, store)
    click.echo(f"{tally['n']} trials in {store_path}: {tally['ok']} succeeded (judged by the simulator), "
               f"{tally['false']} false successes, {tally['error']} errors")
    click.echo(f"report: atd campaign report {store_path}")
    if loaded.task_digests() != tasks:
        _fail("error: a file of the campaign's tasks changed while it ran, so its trials may mix both versions; "
              "run it again into a new --store", EXIT_INVALID)
    if lost:
        _fail(f"error: {lost} failed trials are stored but not recorded in {record_failed} (see the warnings "
              f"above)", EXIT_USAGE)


def _chosen(loaded: LoadedSpec, spec_file: Path, only: tuple[str, ...], trials: int | None,
            record_failed: Path | None, campaign_id: str) -> Plans:
    """The trials asked for; with --record-failed, every recording's name checked before
    anything is written (named with a new campaign's id: a resumed one's is as long)."""
    try:
        chosen = plans(loaded, parse_only(only), trials)
    except ValueError as exc:
        _fail(f"error: {exc}", EXIT_USAGE)
    if not chosen.cells:
        _fail(f"error: no cell of {spec_file} matches {' '.join('--only ' + o for o in only)}", EXIT_USAGE)
    if record_failed is None:
        return chosen
    if not record_failed.is_dir():
        _fail(f"error: --record-failed {record_failed}: no such folder; create it first", EXIT_USAGE)
    chosen = replace(chosen, recordings=real_path(record_failed), campaign=f"{loaded.spec.name}-{campaign_id}")
    problem = chosen.recording_problem()
    if problem:
        _fail(f"error: {problem}", EXIT_USAGE)
    return chosen


@contextmanager
def _ray(address: str | None, workers: int) -> Iterator[None]:
    """Ray joined or started for --ray (None: not asked for), before the store is opened."""
    if address is None:
        yield
        return
    try:
        with ray_joined(address or None, workers):
            yield
    except RayError as exc:
        _fail(f"error: {exc}", EXIT_USAGE)


def _open_store(path: Path, loaded: LoadedSpec, resume: bool, tasks: dict[str, str], campaign_id: str) -> Store:
    try:
        store = Store.create_or_resume(path, loaded.text, loaded.digest, resume, tasks, campaign_id)
    except DamagedStore as exc:
        _fail(f"error: {exc}", EXIT_INVALID)
    except StoreError as exc:
        _fail(f"error: {exc}", EXIT_USAGE)
    if store.keyed_now:
        click.echo(f"note: {path} was made by an earlier atd, which did not record its tasks' content: an edit "
                   f"before this resume cannot be told; from now on it can", err=True)
    return store


def _run(chosen: Plans, store: Store, name: str, workers: int, ray_address: str | None, quiet: bool) -> int:
    """Run the trials the store lacks, each stored as it ends; how many recordings were lost."""
    most = max((chosen.count(cell) for cell, _ in chosen.cells), default=0)
    stored = store.counts(most)
    # A cell of fewer trials than the most counts only its own (a store may hold more of it).
    stored.update({cell.key: len(store.indices(cell, chosen.count(cell))) for cell, _ in chosen.cells
                   if stored.get(cell.key) and chosen.count(cell) < most})
    left = Counter({cell.key: chosen.count(cell) - stored.get(cell.key, 0) for cell, _ in chosen.cells})
    todo = chosen.longest_first().skipping(
        lambda cell: store.indices(cell, chosen.count(cell)) if stored.get(cell.key) else ())
    total = sum(left.values())
    where = f"Ray ({ray_address or 'local'})" if ray_address is not None else f"{workers} worker(s)"
    if not quiet:
        click.echo(f"{name}: {total} trials to run on {where} ({len(chosen) - total} already in {store.path})",
                   err=True)
    progress = Progress(total, left, len(chosen) - total, quiet=quiet)
    lost = 0

    def keep(record: TrialRecord) -> None:
        nonlocal lost
        store.add(record)
        if record.recording_error:
            lost += 1
            progress.note(f"warning: trial {record.index} of {record.cell.key} is stored, its recording is not: "
                          f"{record.recording_error}")
        progress(record)

    signal.signal(signal.SIGTERM, _stop)  # `kill`, a batch scheduler: stop as Ctrl-C does
    try:
        if ray_address is not None:
            run_ray(todo, keep)
        else:
            run_local(todo, workers, keep)
    except (WorkerError, StoreError) as exc:
        progress.close()
        _fail(f"error: {exc}; {progress.done} finished trials are kept in {store.path}", EXIT_USAGE)
    except KeyboardInterrupt:
        progress.close()
        # counted in the store: the stop can land after a trial is stored and before it is counted
        done = _tally(chosen, store)["n"] - (len(chosen) - total)
        _fail(f"stopped: {done} of {total} trials were stored in {store.path}; "
              f"add --resume to the same command to continue", EXIT_INTERRUPTED)
    progress.close()
    return lost


def _tally(chosen: Plans, store: Store) -> Counter[str]:
    """The stored trials asked for, counted one at a time: a campaign of millions is never all in memory."""
    counts = {cell.key: chosen.count(cell) for cell, _ in chosen.cells}
    tally: Counter[str] = Counter()
    try:
        for r in store.each():
            if r.index < counts.get(r.cell.key, 0):
                tally.update(n=1, ok=int(r.judged_succeeded), false=int(r.false_success), error=int(r.status == "error"))
    except StoreError as exc:
        _fail(f"error: {exc}", EXIT_INVALID)
    return tally
