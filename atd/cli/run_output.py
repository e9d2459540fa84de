"""What `atd run` prints: the live progress line, where the objects came to rest, the
outcome as JSON (`--format json`), and what to try next."""

from __future__ import annotations

import shlex
import sys
from pathlib import Path

import click

from atd.runtime.executor import Outcome
from atd.runtime.report import outcome_document
from atd.sim.thread import CapState

CLEAR_LINE = "\x1b[K"  # erase from the cursor to the end of the line (every terminal since the VT100)


class Progress:
    """One line per state entered, with simulated time and real-time factor; on a terminal
    the line below it updates in place while the state runs. Every line written over another
    erases what the longer one left, and `finish` clears the line in place, so what follows
    starts on a line of its own."""

    def __init__(self, quiet: bool) -> None:
        self.quiet = quiet
        self.tty = sys.stderr.isatty()
        self.state = ""

    def __call__(self, state: str, sim: float, wall: float) -> None:
        if self.quiet:
            return
        line = f"[{sim:7.2f} s  {sim / wall if wall else 0:5.1f}x real time]  {state}"
        if state != self.state:
            self.state = state
            click.echo(f"\r{line}{CLEAR_LINE}" if self.tty else line, err=True)
        elif self.tty:
            click.echo(f"\r{line}{CLEAR_LINE}", err=True, nl=False)

    def finish(self) -> None:
        """Clear the line updated in place (the run has ended, or failed to start)."""
        if self.tty and not self.quiet:
            click.echo(f"\r{CLEAR_LINE}", err=True, nl=False)


#: How a summary says where a cap rests (atd/sim/thread.py's `Rest`).
CAP_RESTS = {"bottle": "on its bottle", "held": "held by the robot", "table": "on the table",
             "elsewhere": "neither on its bottle nor on the table nor held"}


def where(positions: dict[str, tuple[float, float, float]], inside: dict[str, list[str]],
          before: dict[str, list[str]], caps: dict[str, CapState]) -> list[str]:
    """Where the objects came to rest, what each container holds at the end, what was
    taken out of it (`before`: what it held when the run began), and where each screw cap is."""
    lines = []
    if len(positions) == 1:
        x, y, z = next(iter(positions.values()))
        lines.append(f"the object rests at ({x:.3f}, {y:.3f}, {z:.3f})")
    elif positions:
        lines.append("the objects rest at: " + ", ".join(f"{name} ({x:.3f}, {y:.3f}, {z:.3f})"
                                                         for name, (x, y, z) in positions.items()))
    for container, names in inside.items():
        lines.append(f"in '{container}' at the end: {', '.join(names) or 'nothing'} "
                     f"({len(names)} of {len(positions)} objects)")
        held = before.get(container, [])
        if held:
            taken = [name for name in held if name not in names]
            lines.append(f"taken out of '{container}': {', '.join(taken) or 'nothing'} "
                         f"({len(taken)} of the {len(held)} it held)")
    for name, cap in caps.items():  # a closed cap's turn, held at 0 by a soft stop, reads -1e-9: not -0.00
        lines.append(f"the cap of '{name}': turned {max(cap.turns, 0.0):.2f} turns, {'off' if cap.free else 'on'} its thread, "
                     f"{CAP_RESTS[cap.rests]}")
    return lines


def document(run: dict, outcome: Outcome, records: list[dict], positions: dict[str, tuple[float, float, float]],
             inside: dict[str, list[str]], outputs: dict[str, Path | None], notes: list[str],
             caps: dict[str, CapState]) -> dict:
    """The run as `--format json` gives it: what ran (`run`), the outcome with its path and
    events, where the objects rest, where the screw caps are, the files asked for and the
    notes the text would print."""
    return {**run, **outcome_document(outcome, records),
            "objects": {name: [round(v, 6) for v in xyz] for name, xyz in positions.items()},
            "caps": {name: {"turns": round(cap.turns, 4), "free": cap.free, "rests": cap.rests,
                            "position": [round(float(v), 6) for v in cap.pose[:3, 3]]} for name, cap in caps.items()},
            "inside": inside,
            "outputs": {name: None if path is None else str(path) for name, path in outputs.items()},
            "notes": notes}


def next_step(command: list[str], record: Path | None, video: Path | None, succeeded: bool) -> str:
    """One line of what to try next, after `command` (the run's `atd run TASK --robot R`)."""
    again = shlex.join(command)
    if record is None:
        why = "the task graph, timeline and signals" + ("" if succeeded else ", and the readings behind the failure")
        return f"next: {again} --record run.mcap, then atd report run.mcap ({why})"
    if video is None:
        return f"next: {again} --video run.gif (the run as an animation, the state and time on each frame)"
    return f"next: {again} --seed 1 --record seed1.mcap, then atd compare {shlex.quote(str(record))} seed1.mcap"
