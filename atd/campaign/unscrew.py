"""What an unscrew trial measures besides the truth (thesis 3.4.2, Table 3.4): how long the
unscrew primitive ran and how many twist moves it made, both as the run's trace has them."""

from __future__ import annotations

from typing import Any, Iterable

from atd.model.estd import Estd
from atd.model.vocabulary import StateType

TWISTS = "twists"  # the count an unscrew's arm ends with (`UnscrewArm.finish`): in its event's evidence


def twists_said(event: dict[str, Any]) -> list[int]:
    """The twist moves (thesis Table 3.4 "Moves") an event's conditions carry from the unscrew
    that ended; none for any other event (a run that ended while it still twisted never said)."""
    return [int(c[TWISTS]) for c in event["conditions"] if TWISTS in c]


def unscrew_measures(belief: Estd, records: Iterable[dict[str, Any]], sim_time: float) -> dict[str, float]:
    """`unscrew_time` (s simulated in unscrew states, a run that ended in one counted to its
    end) and `twists` (the twist moves the unscrews said they made; absent when none said,
    as when a timeout ended one)."""
    unscrews = {f"{prefix}{s.name}" for prefix, machine in belief.walk() for s in machine.states
                if s.type is StateType.UNSCREW}
    time, entered, twists = 0.0, None, []
    for r in records:
        if r["type"] == "enter" and r["state"] in unscrews:
            entered = r["t"]
        elif r["type"] == "exit" and r["state"] in unscrews and entered is not None:
            time, entered = time + r["t"] - entered, None
        elif r["type"] == "event" and r["state"] in unscrews:
            twists += twists_said(r)
    if entered is not None:
        time += sim_time - entered
    return {"unscrew_time": time, **({"twists": float(sum(twists))} if twists else {})}
