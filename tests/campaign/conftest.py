"""Trial records made by hand, shaped like the stores a campaign writes (no simulation), and
how two runs' records are compared."""

from __future__ import annotations

from pathlib import Path

import pytest

from atd.campaign.record import Cell, TrialRecord
from atd.campaign.store import Store

TIMES = ("wall_time", "setup_time")  # the only fields that may differ between two runs of a trial
# Ray starts its workers at nice +15: beside the suite's other busy worker they barely run (a 2 s trial took 25 s)
RAY_WORKERS_AT_OUR_PRIORITY = {"RAY_worker_niceness": "0"}


def outcomes(records: list[TrialRecord]) -> dict:
    """Every field of every record but the wall-clock times, keyed by trial."""
    return {(r.cell.key, r.index): {k: v for k, v in r.as_dict().items() if k not in TIMES} for r in records}


def trial(index: int = 0, *, grasp: str = "naive", perturbation: str = "none", object: str = "mug",
          robot: str = "tombatossals", arm: str = "right", engine: str = "mujoco",
          judged: bool = True, task_said: bool | None = None, status: str = "ok",
          sampled: dict[str, float] | None = None) -> TrialRecord:
    """One trial; the task agrees with the judge unless `task_said` says otherwise."""
    cell = Cell("grasp_and_lift", robot, arm, engine, grasp, object, perturbation)
    return TrialRecord(
        cell=cell, index=index, seed=1000 + index, status=status,  # type: ignore[arg-type]
        error="worker crashed" if status == "error" else "",
        perturbation=sampled or {}, task_succeeded=judged if task_said is None else task_said,
        end_state="done", summary="succeeded: reached 'done'",
        events=[{"time": 2.66, "transition": "grasp->lift", "event": "grasp_stable"}],
        judged_succeeded=judged, judge_reason="lifted 0.08 m, slipped 0.002 m",
        measurements={"lift": 0.08, "slip": 0.002}, sim_time=8.2, wall_time=1.5, setup_time=0.2)


def approach(translation: float, rotation: float) -> dict[str, float]:
    """An approach error of the given size, its components along x and about z."""
    return {"dx": translation, "dy": 0.0, "dz": 0.0, "roll": 0.0, "pitch": 0.0, "yaw": rotation,
            "translation": translation, "rotation": rotation}


def preset_records() -> list[TrialRecord]:
    """Table 3.3's shape: naive and robust, without and with approach error, two objects,
    four trials each; robust succeeds more, and the error hurts naive the most."""
    records = []
    for grasp in ("naive", "robust"):
        for perturbation in ("none", "approach"):
            for obj in ("mug", "duck"):
                for i in range(4):
                    sampled = approach(0.01 * (i + 1), 3.0 * (i + 1)) if perturbation == "approach" else None
                    fails = (grasp == "naive") + (perturbation == "approach") * 2
                    records.append(trial(i, grasp=grasp, perturbation=perturbation, object=obj,
                                         judged=i >= fails, sampled=sampled))
    return records


@pytest.fixture
def preset_store(tmp_path: Path) -> Path:
    path = tmp_path / "table_3_3.sqlite"
    with Store.create_or_resume(path, "[campaign]\ntrials = 4\n", "digest-1", resume=False) as store:
        for record in preset_records():
            store.add(record)
    return path
