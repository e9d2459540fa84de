"""Running a simulation in a child process, so that a crash in an engine's C code (a
segfault, an abort) is an error the parent reports instead of `atd run` vanishing.

The child is forked, not spawned: it starts at once with the task translated and the
modules loaded, and no engine exists yet when it forks, so no engine thread or OpenGL
context is copied. It sends back what the work returned, or the exception it raised;
the parent re-raises that, so callers handle errors as if the work had run in-process.
"""

from __future__ import annotations

import os
import pickle
import signal
import sys
import traceback
from typing import Callable, NoReturn, TypeVar

T = TypeVar("T")

#: Signals that stop `atd run`: the parent passes them on to the child, and ends as the child did.
FORWARDED = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)


class EngineCrash(Exception):
    """The child running the simulation died of a signal it did not ask for."""

    def __init__(self, signum: int) -> None:
        super().__init__(f"killed by {signal_name(signum)}")
        self.signum = signum


def signal_name(signum: int) -> str:
    """SIGSEGV rather than 11, when the number has a name."""
    try:
        return signal.Signals(signum).name
    except ValueError:
        return f"signal {signum}"


def in_child(work: Callable[[], T]) -> T:
    """`work()` run in a forked child: what it returns, or the exception it raises, raised here.

    EngineCrash when the child dies of a signal; KeyboardInterrupt when Ctrl-C (SIGINT)
    stopped it; a SIGTERM or SIGHUP ends both. The result and the exception must pickle.
    """
    _flush()  # or the child would print again what is still buffered here
    reading, writing = os.pipe()
    heeded = [s for s in FORWARDED if signal.getsignal(s) != signal.SIG_IGN]  # ignored ones stay ignored
    signal.pthread_sigmask(signal.SIG_BLOCK, FORWARDED)  # none may land between fork and the handlers
    pid = os.fork()
    if pid == 0:
        os.close(reading)
        if signal.SIGINT in heeded:
            signal.signal(signal.SIGINT, _interrupted_once)
        _child(work, writing)
    os.close(writing)
    previous = {s: signal.signal(s, lambda signum, _: os.kill(pid, signum)) for s in heeded}
    signal.pthread_sigmask(signal.SIG_UNBLOCK, FORWARDED)
    try:
        with os.fdopen(reading, "rb") as pipe:
            sent = pipe.read()
        _, status = os.waitpid(pid, 0)
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)
    if os.WIFSIGNALED(status):
        signum = os.WTERMSIG(status)
        if signum == signal.SIGINT:
            raise KeyboardInterrupt
        if signum in FORWARDED:
            _die_of(signum)  # stopped as asked
        raise EngineCrash(signum)
    succeeded, value = pickle.loads(sent)
    if succeeded:
        return value
    raise value


def _child(work: Callable[[], object], writing: int) -> NoReturn:
    """Run `work`, send its outcome to the parent and end without running the parent's exit code."""
    try:
        try:
            signal.pthread_sigmask(signal.SIG_UNBLOCK, FORWARDED)
            sent = pickle.dumps((True, work()))
        except KeyboardInterrupt:
            _die_of(signal.SIGINT)
        except BaseException as exc:  # noqa: BLE001 - every exception is the parent's to handle
            sent = _pickled_failure(exc)
        with os.fdopen(writing, "wb") as pipe:
            pipe.write(sent)
    finally:
        _flush()
        os._exit(0)


def _pickled_failure(exc: BaseException) -> bytes:
    # where it happened, shown only if the parent prints a traceback (str(exc) is unchanged)
    exc.add_note("".join(traceback.format_exception(exc)).rstrip())
    try:
        return pickle.dumps((False, exc))
    except Exception:  # noqa: BLE001 - an exception that does not pickle still has its words
        return pickle.dumps((False, RuntimeError(f"{type(exc).__name__}: {exc}")))


def _interrupted_once(signum: int, frame: object) -> NoReturn:
    """Ctrl-C on a terminal reaches the child twice (from the terminal, and passed on by the
    parent): the first stops the work, the second must not interrupt the stopping."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    raise KeyboardInterrupt


def _die_of(signum: int) -> NoReturn:
    """End this process by `signum` with its default action, so whoever waits for it sees why."""
    _flush()
    signal.signal(signum, signal.SIG_DFL)
    os.kill(os.getpid(), signum)
    os._exit(128 + signum)  # not reached: the signal ends the process


def _flush() -> None:
    """Push out what is buffered for the terminal; a closed or broken stream is no reason to stop."""
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):
            pass
