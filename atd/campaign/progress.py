"""What a running campaign shows: on a terminal a live bar (trials done of total, success
so far, trials per second, time left); elsewhere (CI, a log file) one plain line per
finished cell, so the log reads as a table."""

from __future__ import annotations

import sys
from collections import Counter
from typing import TextIO

from atd.campaign.record import TrialRecord


class Progress:
    def __init__(self, total: int, per_cell: Counter[str], already: int = 0, stream: TextIO | None = None,
                 quiet: bool = False) -> None:
        self.stream = stream or sys.stderr
        self.quiet = quiet
        self.left = Counter(per_cell)
        self.cells: dict[str, Counter[str]] = {}
        self.done = self.successes = 0
        self.bar = None
        if not quiet and self.stream.isatty():
            from tqdm import tqdm

            self.bar = tqdm(total=total + already, initial=already, unit="trial", file=self.stream,
                            dynamic_ncols=True, smoothing=0.1)

    def __call__(self, record: TrialRecord) -> None:
        self.done += 1
        self.successes += record.judged_succeeded
        key = record.cell.key
        tally = self.cells.setdefault(key, Counter())
        tally.update(n=1, ok=int(record.judged_succeeded), false=int(record.false_success),
                     error=int(record.status == "error"))
        self.left[key] -= 1
        if self.bar is not None:
            self.bar.set_postfix_str(f"success {self.successes}/{self.done} ({self.successes / self.done:.0%})",
                                     refresh=False)
            self.bar.update(1)
        elif not self.quiet and self.left[key] == 0:
            errors = f", {tally['error']} errors" if tally["error"] else ""
            print(f"{key}: {tally['ok']}/{tally['n']} succeeded, {tally['false']} false successes{errors}",
                  file=self.stream, flush=True)

    def note(self, line: str) -> None:
        """A line about one trial, above the bar when there is one."""
        if self.bar is not None:
            self.bar.write(line, file=self.stream)
        else:
            print(line, file=self.stream, flush=True)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
