"""The two guards every command goes through: one for the files it reads, one for the files
it writes.

A user can name anything as a file: a FIFO that never ends, /dev/zero, a device node, the
task itself as the output. Reading goes through `read_capped`, which opens without
blocking, accepts only a regular file and never reads past its cap whatever size the file
claims. Writing goes through `output_problems` before any work and `write_output` at the
end, so nothing is lost, replaced or left half-written.
"""

from __future__ import annotations

import errno
import os
import stat
from pathlib import Path
from typing import Iterable, Mapping

from atd.model.writer import write_atomically

NAME_MAX = 255  # bytes in one path component, on every file system we run on


class InputError(Exception):
    """A file that cannot be read as a task, config or mesh; the message says why."""


class InputTooBig(InputError):
    """A file over the cap of what it may be."""


class OutputError(Exception):
    """A file that must not or could not be written; the message says why and what to do."""


def name_too_long(path: Path) -> str | None:
    """Why a path has a component no file system accepts; None when it has none."""
    for part in path.parts:
        if len(os.fsencode(part)) > NAME_MAX:
            return f"the name '{part[:40]}...' is {len(os.fsencode(part))} bytes, over the {NAME_MAX} a file name may have"
    return None


def unreadable(path: Path) -> str | None:
    """Why `path` is not a file to read, in the words `read_capped` uses; None when it is a
    regular file. Never an exception, also for names no file can have."""
    try:
        return _not_regular(os.stat(path).st_mode)
    except FileNotFoundError:
        return "no such file"
    except OSError as exc:
        return f"cannot read file: {exc.strerror}"
    except ValueError:  # a NUL in the name
        return "no such file"


def _not_regular(mode: int) -> str | None:
    if stat.S_ISDIR(mode):
        return "is a directory, not a file"
    if not stat.S_ISREG(mode):
        return "is not a regular file (a device, FIFO or socket)"
    return None


def real_path(path: Path) -> Path:
    """`path` made absolute, its symbolic links followed as far as they lead. `Path.resolve`
    raises RuntimeError on a symlink loop (Python 3.11), and a user can name one anywhere."""
    return Path(os.path.realpath(path))


def read_capped(path: Path, cap: int) -> bytes:
    """The bytes of a regular file, at most `cap` of them (InputError beyond that).

    The file is opened non-blocking so a FIFO cannot hang us, and checked to be regular
    after opening so a device or a socket is refused; the cap counts what is read,
    since /dev/zero-like files report a size of 0.
    """
    long = name_too_long(path)
    if long:
        raise InputError(long)
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except FileNotFoundError:
        raise InputError("no such file") from None
    except IsADirectoryError:
        raise InputError("is a directory, not a file") from None
    except OSError as exc:
        raise InputError(f"cannot read file: {exc.strerror}") from None
    try:
        kind = _not_regular(os.fstat(fd).st_mode)
        if kind:
            raise InputError(kind)
        chunks, total = [], 0
        while total <= cap:
            chunk = os.read(fd, min(1 << 20, cap + 1 - total))
            if not chunk:
                break
            chunks.append(chunk)
            total += len(chunk)
    except OSError as exc:
        raise InputError(f"cannot read file: {exc.strerror}") from None
    finally:
        os.close(fd)
    if total > cap:
        raise InputTooBig(f"larger than the {cap // 2**20} MiB allowed")
    return b"".join(chunks)


def _same(a: Path, b: Path) -> bool:
    try:
        return os.path.samefile(a, b)
    except OSError:
        return os.path.abspath(a) == os.path.abspath(b)


def output_problem(path: Path) -> str | None:
    """Why `path` alone cannot be written, found before any work is done; None when it can."""
    long = name_too_long(path)
    if long:
        return long
    folder = path.parent
    if not folder.is_dir():
        if folder.exists():
            return f"{folder} is not a folder; write elsewhere"
        return f"the folder {folder} does not exist; create it or write elsewhere"
    if not os.access(folder, os.W_OK):
        return f"the folder {folder} is not writable; write elsewhere"
    try:
        mode = os.stat(path).st_mode
    except FileNotFoundError:
        return None
    except OSError as exc:
        return f"cannot check it: {exc.strerror}"
    if not stat.S_ISREG(mode):
        return "it exists and is not a regular file (a directory, device, FIFO or socket); write elsewhere"
    return None


def output_problems(outputs: Mapping[str, Path | None], inputs: Iterable[Path] = ()) -> list[str]:
    """Every reason the outputs of one command cannot be written, each naming its option.

    `outputs` maps an option (e.g. '-o', '--trace') to its path; an output may not be one
    of the command's `inputs`, nor the same file as another output.
    """
    given = [(option, Path(path)) for option, path in outputs.items() if path is not None]
    sources = [Path(p) for p in inputs]
    problems = []
    for i, (option, path) in enumerate(given):
        problem = output_problem(path)
        if problem:
            problems.append(f"{option} {path}: {problem}")
        if any(_same(path, source) for source in sources):
            problems.append(f"{option} {path}: that is an input of this command and would be overwritten; "
                            "write elsewhere")
        for other_option, other in given[:i]:
            if _same(path, other):
                problems.append(f"{option} {path}: {other_option} names the same file; give each output its own name")
    return problems


def describe_write_error(path: Path, exc: OSError) -> str:
    """A write error in one line a user can act on."""
    advice = {errno.ENOSPC: "free some space or write elsewhere",
              errno.EDQUOT: "free some space or write elsewhere",
              errno.EFBIG: "the file is over the size limit (ulimit -f); raise it or write elsewhere",
              errno.EACCES: "write elsewhere", errno.EPERM: "write elsewhere",
              errno.EROFS: "the file system is read-only; write elsewhere",
              errno.ENAMETOOLONG: "use a shorter name"}
    reason = exc.strerror or str(exc)
    return f"cannot write {path}: {reason}; {advice.get(exc.errno or 0, 'write elsewhere')}"


def write_output(path: Path, data: bytes) -> None:
    """Write a command's output in one step; OutputError (nothing left behind) when it cannot."""
    problem = output_problem(Path(path))
    if problem:
        raise OutputError(f"cannot write {path}: {problem}")
    try:
        write_atomically(Path(path), data)
    except OSError as exc:
        raise OutputError(describe_write_error(Path(path), exc)) from None
