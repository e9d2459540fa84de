"""Two-arm tasks on Baxter: in MuJoCo the holder lifts the cylinder and keeps holding it,
still, while the worker brings its hand beside it (the simulator's truth says it stayed up);
in PyBullet a short task moves each arm in turn, the first holding still while the other moves;
a video of a two-arm run films both arms."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from PIL import Image

from atd.model import load_task
from atd.runtime.session import Run
from atd.sim.video import FRAME_PERIOD
from factories.registry import create
from translator import translate

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "two_arm_hold_and_move.xml"


def _estd(robot: str = "baxter"):
    task, _ = load_task(EXAMPLE)
    return translate(task, create(robot)).estd


def test_the_holder_keeps_the_object_lifted_and_still_while_the_worker_moves() -> None:
    factory = create("baxter")
    run = Run(_estd(), factory, engine="mujoco", seed=0)
    left = run.others["left"]
    assert left.true_tcp()[1, 3] > 0.29  # the added arm starts parked on its own side, out of the way
    during: list[tuple[np.ndarray, np.ndarray]] = []  # (holder's TCP, object) while the worker moves

    def watch(_: float) -> None:
        if run.executor.machine.innermost().visit.path == "come_beside":
            during.append((run.robot.true_tcp()[:3, 3].copy(), run.robot.object_pose()[:3, 3].copy()))

    run.observers.append(watch)
    worker_from = left.true_tcp()[:3, 3].copy()
    outcome = run.execute()
    assert outcome.succeeded, outcome.summary
    assert [v.path for v in outcome.visits][-2:] == ["come_beside", "success_end"]
    tcp, obj = (np.array(x) for x in zip(*during))
    assert len(during) > 100  # the worker moved for more than half a second
    assert np.ptp(tcp, axis=0).max() < 0.005  # the holder's hand held its pose (m)
    assert obj[:, 2].min() > 0.12  # lifted from 4 cm to 16 cm, and kept there (truth)
    assert run.object_position[2] > 0.12
    worker_to = left.true_tcp()[:3, 3]
    assert np.linalg.norm(worker_to - (0.10, 0.16, 0.16)) < 0.01 < np.linalg.norm(worker_from - worker_to)


SHORT = """<statemachine>
  <role name="holder"/>
  <role name="worker"/>
  <object><pose>1 0 0 0.10  0 1 0 0.0  0 0 1 0.04  0 0 0 1</pose><weight>0.15</weight><class>cylinder</class>
    <size>0.02 0.08</size></object>
  <state name="hand_up" type="move" role="holder"><movement>free</movement><hand_shape>open</hand_shape>
    <path><position>0.10 -0.05 0.20</position></path></state>
  <state name="come_beside" type="move" role="worker"><movement>free</movement><hand_shape>open</hand_shape>
    <path><position>0.10 0.16 0.16</position></path></state>
  <state name="done" type="success"/>
  <state name="failed" type="failure"/>
  <transition origin="hand_up" destination="come_beside"><success/></transition>
  <transition origin="come_beside" destination="done"><success/></transition>
  <transition origin="hand_up" destination="failed"><error/></transition>
  <transition origin="come_beside" destination="failed"><error/></transition>
</statemachine>
"""


def test_a_two_arm_task_runs_in_pybullet_one_arm_after_the_other(tmp_path: Path) -> None:
    path = tmp_path / "two.xml"
    path.write_text(SHORT)
    task, _ = load_task(path)
    run = Run(translate(task, create("baxter")).estd, create("baxter"), engine="pybullet", seed=0)
    left = run.others["left"]
    assert left.true_tcp()[1, 3] > 0.29  # parked on its own side
    holder: list[np.ndarray] = []  # the holder's TCP while the worker moves

    def watch(_: float) -> None:
        if run.executor.machine.innermost().visit.path == "come_beside":
            holder.append(run.robot.true_tcp()[:3, 3].copy())

    run.observers.append(watch)
    outcome = run.execute()
    assert outcome.succeeded, outcome.summary
    assert len(holder) > 100 and np.ptp(np.array(holder), axis=0).max() < 0.002  # held still (m)
    assert np.linalg.norm(run.robot.true_tcp()[:3, 3] - (0.10, -0.05, 0.20)) < 0.005
    assert np.linalg.norm(left.true_tcp()[:3, 3] - (0.10, 0.16, 0.16)) < 0.005


def test_a_two_arm_run_on_video_films_the_worker_moving_while_the_holder_holds(tmp_path: Path) -> None:
    path = tmp_path / "two.xml"
    path.write_text(SHORT)
    task, _ = load_task(path)
    gif = tmp_path / "run.gif"
    run = Run(translate(task, create("baxter")).estd, create("baxter"), engine="mujoco", seed=0, video=gif,
              video_size=(160, 120))
    outcome = run.execute()
    assert outcome.succeeded, outcome.summary
    assert f"video: {gif}" in run.notes[-1]
    with Image.open(gif) as frames:
        pictures = []
        for index in range(frames.n_frames):
            frames.seek(index)
            pictures.append(np.asarray(frames.convert("RGB"), dtype=int)[20:])  # below the state's label
    worker = next(v for v in outcome.visits if v.path == "come_beside")
    during = pictures[int(worker.entered / FRAME_PERIOD) + 1:int(worker.left / FRAME_PERIOD)]
    assert len(pictures) >= int(worker.left / FRAME_PERIOD) and len(during) >= 5
    # Only the worker moves then (the holder holds still, tested above): the film draws that arm too.
    changed = np.abs(during[-1] - during[0]).max(axis=2) > 60
    assert changed.sum() > 100
