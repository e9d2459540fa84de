"""What a campaign's trials read besides the spec, and a digest of each. A store is keyed to
them as well as to the spec, so `--resume` after a task was edited is refused rather than
mixing trials of the old task and the new into one rate."""

from __future__ import annotations

import hashlib
import os
from pathlib import Path
from typing import Iterable

from atd.model import load_task
from atd.model.files import InputError, read_capped, real_path
from atd.model.meshcheck import MAX_BYTES as MESH_BYTES
from atd.model.validate import subtask_path
from atd.model.vocabulary import StateType


def sources(task_file: Path) -> list[Path]:
    """The task file, every sub-task it includes at any depth, and each one's object mesh."""
    found: dict[Path, None] = {}
    frontier = [real_path(task_file)]
    while frontier:
        path = frontier.pop()
        if path in found:
            continue
        found[path] = None
        task, _ = load_task(path)
        if task is None:
            continue
        if task.object is not None and task.object.shape:
            found[real_path(path.parent / task.object.shape)] = None
        frontier += [real_path(subtask_path(task, s)) for s in task.states if s.type is StateType.TASK and s.file]
    return list(found)


def digests(task_files: Iterable[Path], folder: Path) -> dict[str, str]:
    """The SHA-256 of every source of the tasks, by its path relative to `folder` (the
    spec's): a campaign folder moved or cloned whole keeps its key."""
    return {os.path.relpath(path, folder): _digest(path) for task in task_files for path in sources(task)}


def _digest(path: Path) -> str:
    try:
        return hashlib.sha256(read_capped(path, MESH_BYTES)).hexdigest()
    except InputError as exc:  # a mesh the task names but that is missing (a warning, not an error)
        return f"unreadable: {exc}"
