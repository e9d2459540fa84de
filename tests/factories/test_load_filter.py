"""load_held's low pass follows the wrist sensor the robot's description says it has: on
the Baxter's virtual wrist (1 N of noise a reading) an empty hand must not read as a light
object held, and a held one must still show within the transport's hold."""

from __future__ import annotations

import numpy as np

from atd.campaign.objects import get
from atd.model import load_task
from atd.model.estd import leaves
from atd.model.frames import GRAVITY
from atd.sim.sensors import NoisySensors
from factories.base import HELD_FOR
from factories.registry import create
from primitives.filters import LowPass
from tests.conftest import EXAMPLES
from translator import translate

LIFT = 20.0  # s: the transport's timeout in examples/grasp_and_lift.xml


def _load_held(robot: str, arm: str, obj: str):
    task, _ = load_task(EXAMPLES / "grasp_and_lift.xml")
    factory = create(robot, arm)
    estd = translate(task.model_copy(update={"object": get(obj).object_info(0.10, 0.0)}), factory).estd
    found = [leaf for t in estd.transitions for e in t.events for leaf in leaves(e.condition) if leaf.kind == "load_held"]
    return found[0], factory


def _filtered_noise(factory, tau: float, seconds: float, seed: int) -> np.ndarray:
    """The wrist's z force on a still, empty hand as the sensor reports it, through load_held's low pass."""
    period = factory.robot.control_period
    sensors = NoisySensors([(factory.robot.sensors["wrench"], 6)], np.random.default_rng(seed), period)
    low, out = LowPass(tau), []
    for _ in range(round(seconds / period)):
        x = np.zeros(6)
        sensors(x)
        out.append(low(x, period)[2].copy())
    return np.array(out)


def test_the_baxter_empty_hand_never_reads_as_the_tape_roll_held_during_a_lift() -> None:
    load, factory = _load_held("baxter", "left", "tape")  # 60 g: half of it is 0.29 N
    for seed in range(3):
        noise = _filtered_noise(factory, float(load.params["filter_time"]), LIFT, seed)
        bias = noise[len(noise) // 2:].mean()  # the sensor's own bias: the empty hand's reading takes it too
        assert np.abs(noise[round(1.0 / factory.robot.control_period):] - bias).max() / GRAVITY < load.params["weight"]


def test_the_low_pass_settles_on_a_held_load_within_the_transport_hold() -> None:
    load, _ = _load_held("baxter", "left", "duck")  # 30 g: the lightest everyday object
    tau = float(load.params["filter_time"])
    assert tau <= HELD_FOR and 1.0 - np.exp(-HELD_FOR / tau) > 0.5  # the weight's half shows by the hold's end


def test_a_quiet_wrist_keeps_the_short_low_pass() -> None:
    for robot, arm in (("melfa", "main"), ("tombatossals", "left"), ("panda", "main")):
        load, _ = _load_held(robot, arm, "duck")
        assert load.params["filter_time"] == 0.05, robot
