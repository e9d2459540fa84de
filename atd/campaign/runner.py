"""Running a campaign's trials: in local worker processes or on Ray, each record
committed to the store as soon as its trial ends.

The local pool is our own, not `concurrent.futures`: there, one worker killed by a
crash in an engine's C code breaks the whole pool; here the parent sees which trial the
dead worker had, records it as an error trial, starts a new worker and goes on. A trial
that outlives its hard wall-clock limit (a hang inside an engine, where the watchdog
cannot reach) is ended the same way.
"""

from __future__ import annotations

import multiprocessing as mp
import os
import queue
import signal
import time
from typing import Callable

from atd.campaign.cells import TrialPlan
from atd.campaign.record import TrialRecord
from atd.campaign.trial import run_trial
from atd.runtime.isolated import signal_name

Sink = Callable[[TrialRecord], None]  # takes each finished trial (the store, the progress display)
#: Wall-clock seconds per simulated second of budget before a trial counts as hung: far
#: slower than any engine runs here (PyBullet's slowest run is about 3x real time).
HANG_FACTOR = 4.0
HANG_FLOOR = 120.0  # s


def run_local(plans: list[TrialPlan], workers: int, sink: Sink) -> None:
    """Run the plans on `workers` processes (1: in this process); each record goes to `sink`."""
    if workers <= 1:
        for plan in plans:
            sink(run_trial(plan))
        return
    _Pool(workers, sink).run(plans)


def run_ray(plans: list[TrialPlan], address: str | None, workers: int, sink: Sink) -> None:
    """Run the plans as Ray tasks, on a local Ray instance or the cluster at `address`."""
    import ray

    started_here = not ray.is_initialized()
    if started_here:
        options = {"address": address} if address else {"num_cpus": workers, "include_dashboard": False}
        ray.init(log_to_driver=False, configure_logging=False, **options)
    remote = ray.remote(max_retries=0)(run_trial)
    try:
        pending = {remote.remote(plan): plan for plan in plans}
        while pending:
            done, _ = ray.wait(list(pending), num_returns=1)
            plan = pending.pop(done[0])
            try:
                record = ray.get(done[0])
            except Exception as exc:  # noqa: BLE001 - a worker that died is that trial's result
                record = _crashed(plan, f"the Ray worker failed: {type(exc).__name__}: {str(exc).splitlines()[0]}")
            sink(record)
    finally:
        if started_here:
            ray.shutdown()


class WorkerError(RuntimeError):
    """The pool cannot run: its worker processes die before they take a trial."""


def hang_limit(plan: TrialPlan) -> float:
    return max(HANG_FLOOR, HANG_FACTOR * plan.budget)


def _crashed(plan: TrialPlan, why: str) -> TrialRecord:
    return TrialRecord(cell=plan.cell, index=plan.index, seed=plan.seed, status="error", error=why)


def _work(todo: mp.Queue, done: mp.Queue) -> None:
    """A worker: take plans until told to stop, say which one it starts, send each record."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the parent's to handle
    while (item := todo.get()) is not None:
        number, plan = item
        done.put(("start", os.getpid(), number))
        done.put(("done", os.getpid(), run_trial(plan)))


def _worker_context() -> mp.context.BaseContext:
    """Workers forked from a server that has imported the trial code once, and no engine:
    a plain fork would copy whatever engines and threads the caller holds."""
    if "forkserver" not in mp.get_all_start_methods():
        return mp.get_context("spawn")
    context = mp.get_context("forkserver")
    context.set_forkserver_preload(["atd.campaign.trial"])
    return context


class _Pool:
    def __init__(self, workers: int, sink: Sink) -> None:
        self.size = workers
        self.sink = sink
        self.context = _worker_context()
        self.todo = self.context.Queue()
        self.done = self.context.Queue()
        self.workers: dict[int, mp.Process] = {}
        self.running: dict[int, tuple[int, float]] = {}  # pid -> (plan number, started)
        self.reported: set[int] = set()  # workers that have sent anything
        self.lost = ""  # why trials a worker took but never announced have no record

    def _start_worker(self) -> None:
        process = self.context.Process(target=_work, args=(self.todo, self.done), daemon=True)
        process.start()
        self.workers[process.pid] = process

    def run(self, plans: list[TrialPlan]) -> None:
        for number, plan in enumerate(plans):
            self.todo.put((number, plan))
        for _ in range(min(self.size, len(plans))):
            self._start_worker()
        for _ in self.workers:
            self.todo.put(None)
        left = set(range(len(plans)))
        try:
            while left:
                self._take(left)
                self._reap(plans, left)
                if not self.workers:  # all gone, every plan taken: what is left, a dead worker took
                    for number in sorted(left):
                        self.sink(_crashed(plans[number], self.lost))
                    left.clear()
        finally:
            for channel in (self.todo, self.done):  # plans nobody will take must not hold up the exit
                channel.cancel_join_thread()
            for process in self.workers.values():
                if process.is_alive():
                    process.kill()
                process.join()

    def _reap(self, plans: list[TrialPlan], left: set[int]) -> None:
        """Dead or hung workers: their trial is an error trial, and a new worker takes over."""
        for pid, process in list(self.workers.items()):
            number, since = self.running.get(pid, (None, 0.0))
            hung = number is not None and time.monotonic() - since > hang_limit(plans[number])
            if process.is_alive() and not hung:
                continue
            if hung:
                process.kill()
            process.join()
            del self.workers[pid]
            self._drain(left)  # what it sent before it ended still counts
            died = f"the worker process died ({_exit_reason(process.exitcode)})"
            if pid in self.running:
                number, _ = self.running.pop(pid)
                left.discard(number)
                why = f"the trial hung: no result after {hang_limit(plans[number]):g} s of wall-clock time"
                self.sink(_crashed(plans[number], why if hung else died))
            elif process.exitcode == 0:
                continue  # it finished its share
            elif pid not in self.reported:
                raise WorkerError(f"a worker process could not start ({_exit_reason(process.exitcode)}); "
                                  f"run with --workers 1 to see why")
            # It may have taken a plan it never announced (killed between trials, or before what
            # it last sent left it): no one else will take that one; `run` records it at the end.
            self.lost = f"{died} before reporting the trial"
            self._start_worker()
            self.todo.put(None)

    def _drain(self, left: set[int]) -> None:
        while self._take(left, block=False):
            pass

    def _take(self, left: set[int], block: bool = True) -> bool:
        """Handle one message from the workers; False when none came."""
        try:
            kind, pid, payload = self.done.get(timeout=0.5) if block else self.done.get_nowait()
        except queue.Empty:
            return False
        self.reported.add(pid)
        if kind == "start":
            self.running[pid] = (payload, time.monotonic())
        else:
            number, _ = self.running.pop(pid)
            left.discard(number)
            self.sink(payload)
        return True


def _exit_reason(code: int | None) -> str:
    if code is not None and code < 0:
        return f"killed by {signal_name(-code)}"
    return f"exit code {code}"

