"""Running a campaign's trials: in local worker processes or on Ray, each record
committed to the store as soon as its trial ends.

The local pool is our own, not `concurrent.futures`: there, one worker killed by a
crash in an engine's C code breaks the whole pool; here the parent sees which trial the
dead worker had, records it as an error trial, starts a new worker and goes on. A trial
that outlives its hard wall-clock limit (a hang inside an engine, where the watchdog
cannot reach) is ended the same way.
"""

from __future__ import annotations

import itertools
import multiprocessing as mp
import signal
import socket
import time
from collections import deque
from contextlib import contextmanager
from multiprocessing.connection import Connection, wait
from typing import Callable, Iterable, Iterator

from atd.campaign.cells import TrialPlan
from atd.campaign.record import TrialRecord
from atd.campaign.trial import run_trial
from atd.runtime.isolated import signal_name

Sink = Callable[[TrialRecord], None]  # takes each finished trial (the store, the progress display)
#: Wall-clock seconds past a trial's own watchdog (`TrialPlan.wall_limit`) before its worker
#: counts as hung (inside an engine's C code, where the watchdog cannot reach).
HANG_GRACE = 120.0
#: Ray tasks submitted ahead of those finished: enough to fill a cluster, few enough that a
#: campaign of millions of trials is not all submitted (and held in memory) at once.
RAY_AHEAD = 10_000
#: Plans a local worker holds at once: the one it runs and the next (see `_Pool`).
BATCH = 2
#: What the forkserver imports before it forks a worker (multiprocessing skips it silently if it fails).
WORKER_PRELOAD = "atd.campaign.preload"


def run_local(plans: Iterable[TrialPlan], workers: int, sink: Sink) -> None:
    """Run the plans on `workers` processes (1: in this process); each record goes to `sink`."""
    if workers <= 1:
        for plan in plans:
            sink(run_trial(plan))
        return
    _Pool(workers, sink).run(plans)


class RayError(RuntimeError):
    """Ray cannot run the trials: nothing answers at the cluster's address, or Ray cannot join it."""


@contextmanager
def ray_joined(address: str | None, workers: int) -> Iterator[None]:
    """Ray for the block: the cluster at `address` joined, or a local instance of `workers`
    CPUs started; Ray that this process has already set up is used as it is. Before any
    store is written, so a wrong address costs no `--resume`."""
    import ray

    if ray.is_initialized():
        yield
        return
    if address and (why := _unreachable(address)):
        raise RayError(f"--ray {address}: nothing answers there ({why}); start the cluster's head with "
                       f"`ray start --head --port=PORT` and give HOST:PORT as it prints it")
    options = {"address": address} if address else {"num_cpus": workers, "include_dashboard": False}
    try:
        ray.init(log_to_driver=False, configure_logging=False, **options)
    except Exception as exc:  # noqa: BLE001 - ConnectionError, AuthenticationError, ValueError: all say "cannot join"
        raise RayError(_join_failure(address, exc)) from exc
    try:
        yield
    finally:
        ray.shutdown()


def _unreachable(address: str) -> str | None:
    """Why nothing answers at HOST:PORT (Ray itself would retry for minutes); None when something
    does, or the address is not HOST:PORT ("auto", "ray://...")."""
    host, sep, port = address.rpartition(":")
    if not sep or not port.isdigit() or "://" in address:
        return None
    try:
        socket.create_connection((host.strip("[]"), int(port)), timeout=5).close()
    except OSError as exc:
        return exc.strerror or str(exc) or type(exc).__name__
    return None


def _join_failure(address: str | None, exc: Exception) -> str:
    why = str(exc).splitlines()[0].split(". ")[0] if str(exc) else type(exc).__name__
    if not address:
        return f"--ray: Ray could not start a local instance ({why})"
    return (f"--ray {address}: Ray could not join the cluster there ({why}); a cluster started with "
            f"RAY_AUTH_MODE=token also needs RAY_AUTH_MODE=token and its token here "
            f"(RAY_AUTH_TOKEN_PATH, or ~/.ray/auth_token)")


def run_ray(plans: Iterable[TrialPlan], sink: Sink) -> None:
    """Run the plans as Ray tasks on the Ray of `ray_joined`; each record goes to `sink`."""
    import ray

    remote = ray.remote(max_retries=0)(run_trial)
    todo = iter(plans)
    pending = {remote.remote(plan): plan for plan in itertools.islice(todo, RAY_AHEAD)}
    while pending:
        done, _ = ray.wait(list(pending), num_returns=1)
        plan = pending.pop(done[0])
        pending.update((remote.remote(p), p) for p in itertools.islice(todo, 1))
        try:
            record = ray.get(done[0])
        except Exception as exc:  # noqa: BLE001 - a worker that died is that trial's result
            record = _crashed(plan, f"the Ray worker failed: {type(exc).__name__}: {str(exc).splitlines()[0]}")
        sink(record)


class WorkerError(RuntimeError):
    """The pool cannot run: its worker processes die before they take a trial."""


def _crashed(plan: TrialPlan, why: str) -> TrialRecord:
    return TrialRecord(cell=plan.cell, index=plan.index, seed=plan.seed, status="error", error=why)


def _work(conn: Connection) -> None:
    """A worker: say it is ready, then run each plan it is sent and send back its record,
    until told to stop."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the parent's to handle
    conn.send("ready")
    while (plan := conn.recv()) is not None:
        conn.send(run_trial(plan))


def _worker_context() -> mp.context.BaseContext:
    """Workers forked from a server that has loaded the trial code and MuJoCo once
    (WORKER_PRELOAD), and built no engine: a plain fork would copy whatever engines and
    threads the caller holds."""
    if "forkserver" not in mp.get_all_start_methods():
        return mp.get_context("spawn")
    context = mp.get_context("forkserver")
    context.set_forkserver_preload([WORKER_PRELOAD])
    return context


class _Pool:
    """Each worker has its own pipe: the parent hands plans to a worker and reads its records
    on that worker's connection. With one queue shared by all, a worker killed while it
    waited for a plan kept the queue's lock, and every other worker waited for it forever.

    A worker holds up to BATCH plans: the one it runs and the next, which it starts as soon as
    it has sent a record, without waiting for the parent to store that record and answer. A
    next plan is handed out only while more plans are left than there are workers: near the
    end a plan never waits behind another trial while some worker has nothing to do."""

    def __init__(self, workers: int, sink: Sink) -> None:
        self.size = workers
        self.sink = sink
        self.context = _worker_context()
        self.conns: dict[int, Connection] = {}  # pid -> the parent's end of its pipe
        self.workers: dict[int, mp.Process] = {}
        self.running: dict[int, tuple[TrialPlan, float]] = {}  # pid -> (the plan it runs, since when)
        self.queued: dict[int, deque[TrialPlan]] = {}  # pid -> plans it holds, to run after that one
        self.todo: Iterator[TrialPlan] = iter(())
        self.ahead: deque[TrialPlan] = deque()  # plans taken from `todo`, not yet handed out
        self.ready: set[int] = set()  # workers that have said they started

    def _start_worker(self) -> None:
        parent, child = self.context.Pipe()
        process = self.context.Process(target=_work, args=(child,), daemon=True)
        process.start()
        child.close()
        self.workers[process.pid] = process
        self.conns[process.pid] = parent
        self.queued[process.pid] = deque()

    def run(self, plans: Iterable[TrialPlan]) -> None:
        self.todo = iter(plans)
        self._left(self.size)
        for _ in range(len(self.ahead)):  # a worker each, no more than there are plans
            self._start_worker()
        try:
            while self.workers:
                by_conn = {conn: pid for pid, conn in self.conns.items()}
                for conn in wait(list(by_conn), timeout=0.5):
                    self._receive(by_conn[conn])
                self._reap_hung()
        finally:
            for pid, process in self.workers.items():
                if process.is_alive():
                    process.kill()
                process.join()
                self.conns[pid].close()

    def _receive(self, pid: int) -> None:
        """A message from a worker: ready, a record, or its end (EOF)."""
        try:
            message = self.conns[pid].recv()
        except (EOFError, OSError):
            self._ended(pid)
            return
        if message == "ready":
            self.ready.add(pid)
        else:
            self.running.pop(pid)
            if self.queued[pid]:  # it has started its next plan on sending this record
                self.running[pid] = (self.queued[pid].popleft(), time.monotonic())
            self.sink(message)
        self._hand_out(pid)

    def _left(self, count: int) -> bool:
        """Whether `count` plans are left to hand out, taking them from `todo` to know."""
        if len(self.ahead) < count:
            self.ahead.extend(itertools.islice(self.todo, count - len(self.ahead)))
        return len(self.ahead) >= count

    def _hand_out(self, pid: int) -> None:
        """Fill a worker up to BATCH plans (a next one only while more plans are left than
        workers), or tell an idle worker to stop (None) when none is left."""
        if pid not in self.running:
            if not self._left(1):
                self._send(pid, None)
                return
            self.running[pid] = (self.ahead[0], time.monotonic())
            self._send(pid, self.ahead.popleft())
        while 1 + len(self.queued[pid]) < BATCH and self._left(self.size + 1):
            self.queued[pid].append(self.ahead[0])
            self._send(pid, self.ahead.popleft())

    def _send(self, pid: int, plan: TrialPlan | None) -> None:
        try:
            self.conns[pid].send(plan)
        except OSError:  # it has just died: its pipe reads EOF next, and `_ended` sees to its plans
            pass

    def _ended(self, pid: int, why: str | None = None) -> None:
        """A worker is gone: its trial, if it had one, is an error trial; the plans it held and
        had not started go back to be handed out; a new worker takes over while plans are left."""
        process = self.workers.pop(pid)
        process.join()
        self.conns.pop(pid).close()
        self.ahead.extendleft(reversed(self.queued.pop(pid)))
        if pid in self.running:
            plan, _ = self.running.pop(pid)
            self.sink(_crashed(plan, why or f"the worker process died ({_exit_reason(process.exitcode)})"))
        elif process.exitcode != 0 and pid not in self.ready:
            raise WorkerError(f"a worker process could not start ({_exit_reason(process.exitcode)}); "
                              f"run with --workers 1 to see why")
        if self._left(1):
            self._start_worker()

    def _reap_hung(self) -> None:
        """A trial past its wall-clock limit (a hang inside an engine) ends its worker."""
        for pid, (plan, since) in list(self.running.items()):
            limit = plan.wall_limit + HANG_GRACE
            if time.monotonic() - since > limit:
                self.workers[pid].kill()
                self._ended(pid, f"the trial hung: no result after {limit:g} s of wall-clock time")


def _exit_reason(code: int | None) -> str:
    if code is not None and code < 0:
        return f"killed by {signal_name(-code)}"
    return f"exit code {code}"

