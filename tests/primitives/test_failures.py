"""Things going wrong mid-task, and the ATD failure edge each must end the run through."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from atd.model.vocabulary import EventType
from tests.primitives.conftest import EXAMPLES, Stage, both_done, events, execute, leaf, machine, melfa, run_example, use

PICK_AND_PLACE = EXAMPLES / "pick_and_place.xml"


class AtState:
    """A hook that does something once, `after` s into the first visit of a state."""

    def __init__(self, state: str, after: float, action) -> None:
        self.state, self.after, self.action = state, after, action
        self.entered: float | None = None
        self.done_at: float | None = None

    def __call__(self, robot, state: str, time: float) -> None:
        if state == self.state and self.entered is None:
            self.entered = time
        if self.entered is not None and self.done_at is None and time >= self.entered + self.after:
            self.action(robot)
            self.done_at = time


def _fired(executor, event: str) -> dict:
    found = [r for r in events(executor) if r["event"] == event]
    assert found, f"no {event} event; events: {[r['event'] for r in events(executor)]}"
    return found[0]


def test_removing_the_object_mid_transport_ends_through_grasp_lost() -> None:
    away = np.eye(4)
    away[:3, 3] = (0.3, -0.3, 0.025)
    hook = AtState("carry", 0.3, lambda robot: robot.place_object(away))
    outcome, executor, _ = run_example(PICK_AND_PLACE, hook)
    assert not outcome.succeeded
    assert outcome.summary == "failed in 'carry' on grasp_lost, abstract edge carry -> failed#1"
    lost = _fired(executor, "grasp_lost")
    latency = lost["t"] - hook.done_at
    assert latency <= 0.1, f"grasp_lost came {latency * 1000:.0f} ms after the object left"
    pads = lost["conditions"][0]["pad_force"]
    assert all(force < 2.0 for force in pads.values())


def test_a_free_move_into_an_obstacle_ends_through_collision(tmp_path: Path) -> None:
    task = tmp_path / "blocked.xml"
    task.write_text("""<statemachine>
      <object><pose>1 0 0 0.10  0 1 0 -0.05  0 0 1 0.025  0 0 0 1</pose><class>box</class>
        <size>0.05 0.05 0.05</size></object>
      <environment><obstacle size="0.12 0.04 0.12">0.2 0.15 0.06</obstacle></environment>
      <state name="reach" type="move"><movement>free</movement>
        <path><position>0.25 0.25 0.08</position></path></state>
      <state name="done" type="success"/>
      <state name="failed" type="failure"/>
      <transition origin="reach" destination="done"><success/></transition>
      <transition origin="reach" destination="failed"><collision/></transition>
      <transition origin="reach" destination="failed"><timeout>10</timeout></transition>
    </statemachine>""")
    outcome, executor, _ = run_example(task)
    assert not outcome.succeeded
    assert "on collision" in outcome.summary, outcome.summary
    hit = _fired(executor, "collision")["conditions"][0]
    assert hit["force"] > hit["threshold"] == 15.0
    assert outcome.sim_time < 3.0


@pytest.mark.parametrize("sensor", ["tactile", "wrench", "joints"])
def test_a_sensor_frozen_mid_run_ends_through_hardware_failure(sensor: str) -> None:
    hook = AtState("carry", 0.3, lambda robot: robot.freeze(sensor))
    outcome, executor, _ = run_example(PICK_AND_PLACE, hook)
    assert not outcome.succeeded
    assert "on hardware_failure" in outcome.summary, outcome.summary
    failure = _fired(executor, "hardware_failure")
    assert failure["t"] - hook.done_at <= 0.1
    frozen = [c for c in failure["conditions"] if c.get("frozen_sensor")]
    assert frozen and frozen[0]["frozen_sensor"] == sensor


def test_a_diverging_simulation_ends_through_hardware_failure(tmp_path: Path, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)  # MuJoCo writes its warning to MUJOCO_LOG.TXT in the working directory
    robot = melfa()
    unstable = leaf("simulation_unstable")
    estd = machine(Stage(use("cartesian_move", target=(0.05, 0.1, 0.2)), use("hold_position"), both_done()),
                   failures={"s0": (EventType.HARDWARE_FAILURE, unstable)})

    def blow_up(robot) -> None:
        robot.data.qvel[:] = np.nan  # the engine meets NaNs mid-step

    hook = AtState("s0", 0.3, blow_up)
    outcome, executor = execute(estd, robot, hook)
    assert not outcome.succeeded
    failure = _fired(executor, "hardware_failure")
    assert failure["t"] - hook.done_at <= 0.02
    assert failure["conditions"][0].get("non_finite") or max(failure["conditions"][0]["joint_jump"]) > 0.1


@pytest.mark.parametrize(("robot", "arm"), [("melfa", None), ("baxter", "right"), ("tombatossals", "right"),
                                            ("tombatossals", "left")])
def test_an_object_that_slips_out_while_lifting_is_grasped_again(robot: str, arm: str | None) -> None:
    """retry_grasp.xml's cycle (thesis 3.2): the lift loses the object, which falls back onto the
    table where it lay, and the task goes round again through 'approach' and lifts it."""
    start = np.eye(4)
    start[:3, 3] = (0.10, 0.0, 0.025)
    hook = AtState("lift", 0.6, lambda sim: sim.place_object(start))  # the hand some 4 cm up by then
    outcome, executor, sim = run_example(EXAMPLES / "retry_grasp.xml", hook, robot, arm)
    assert outcome.succeeded, outcome.summary
    path = [v.atd for v in outcome.visits]
    assert path.count("approach") == 2 and path[-1] == "done", path
    assert _fired(executor, "grasp_lost")["t"] - hook.done_at <= 0.2  # Baxter's gripper force is filtered: 0.11 s
    assert sim.object_pose()[2, 3] > 0.1  # held up at the end of the second lift
