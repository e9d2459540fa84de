"""`atd campaign run`: run a campaign spec's trials into a store."""

from __future__ import annotations

import os
import signal
from collections import Counter
from importlib.util import find_spec
from pathlib import Path

import click

from atd.campaign.cells import parse_only, plans
from atd.campaign.progress import Progress
from atd.campaign.runner import WorkerError, run_local, run_ray
from atd.campaign.spec import load_spec
from atd.campaign.store import Store, StoreError
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
        _fail("error: --ray needs Ray, which is not installed; pip install 'atd[ray]'", EXIT_USAGE)
    loaded, found = load_spec(spec_file)
    if loaded is None or has_errors(found):
        _fail(render_all(found), EXIT_INVALID)
    try:
        chosen = plans(loaded, parse_only(only), trials, record_failed and real_path(record_failed))
    except ValueError as exc:
        _fail(f"error: {exc}", EXIT_USAGE)
    if not chosen:
        _fail(f"error: no cell of {spec_file} matches {' '.join('--only ' + o for o in only)}", EXIT_USAGE)
    if record_failed is not None and not record_failed.is_dir():
        _fail(f"error: --record-failed {record_failed}: no such folder; create it first", EXIT_USAGE)
    store_path = store_path or Path.cwd() / f"{loaded.spec.name}.sqlite"
    guard_outputs({"--store": store_path}, [loaded.task_path(entry) for entry in loaded.spec.task_entries])
    try:
        store = Store.create_or_resume(store_path, loaded.text, loaded.digest, resume)
    except StoreError as exc:
        _fail(f"error: {exc}", EXIT_USAGE)
    with store:
        finished = store.done()
        todo = [p for p in chosen if (p.cell.key, p.index) not in finished]
        workers = workers or os.cpu_count() or 1
        where = f"Ray ({ray_address or 'local'})" if ray_address is not None else f"{workers} worker(s)"
        if not quiet:
            click.echo(f"{spec_file.name}: {len(todo)} trials to run on {where} "
                       f"({len(chosen) - len(todo)} already in {store_path})", err=True)
        progress = Progress(len(todo), Counter(p.cell.key for p in todo), len(chosen) - len(todo), quiet=quiet)

        def keep(record) -> None:
            store.add(record)
            progress(record)

        signal.signal(signal.SIGTERM, _stop)  # `kill`, a batch scheduler: stop as Ctrl-C does
        try:
            if ray_address is not None:
                run_ray(todo, ray_address or None, workers, keep)
            else:
                run_local(todo, workers, keep)
        except (WorkerError, StoreError) as exc:
            progress.close()
            _fail(f"error: {exc}; {progress.done} finished trials are kept in {store_path}", EXIT_USAGE)
        except KeyboardInterrupt:
            progress.close()
            _fail(f"stopped: {progress.done} of {len(todo)} trials were stored in {store_path}; "
                  f"add --resume to the same command to continue", EXIT_INTERRUPTED)
        progress.close()
        records = store.records()
    keys = {(p.cell.key, p.index) for p in chosen}
    mine = [r for r in records if (r.cell.key, r.index) in keys]
    successes = sum(r.judged_succeeded for r in mine)
    false = sum(r.false_success for r in mine)
    errors = sum(r.status == "error" for r in mine)
    click.echo(f"{len(mine)} trials in {store_path}: {successes} succeeded (judged by the simulator), "
               f"{false} false successes, {errors} errors")
    click.echo(f"report: atd campaign report {store_path}")
