"""A place blocked on its way over the target ends: the Baxter, bringing a spray can down over a
pile of what it had put down, pressed it into the pile at 111 N for 100 s, the place neither
done nor failed, until the task's timeout (docs/empty-the-box.md, base seed 70919)."""

from __future__ import annotations

import numpy as np

from atd.model.estd import Controller
from atd.sim import load_description
from atd.sim.simrobot import robot_info
from primitives.base import Context, Status
from primitives.registry import build_controller
from primitives.robot import Readings

BAXTER = robot_info(load_description("baxter"))
PRESSED_FROM = 1.0  # s: the hand stops on the pile once it has been brought some way


def _arm(time: float, at: tuple[float, float, float], force: float) -> Readings:
    """The Baxter's hand at `at`, top-down, its wrist pushed up by `force` N."""
    zeros = np.zeros(7)
    tcp = np.diag([1.0, -1.0, -1.0, 1.0])
    tcp[:3, 3] = at
    return Readings(time=time, arm_q=zeros, arm_dq=zeros, arm_effort=zeros, hand_q=np.zeros(1),
                    hand_dq=np.zeros(1), hand_effort=np.zeros(1), tcp=tcp,
                    wrench=np.array([0.0, 0.0, force, 0.0, 0.0, 0.0]), taxels={}, pad_force=np.zeros(2), range=None)


def _place(force: float, seconds: float) -> tuple[object, float]:
    """A place to (0.10, 0.20, 0) whose hand stands still 8 cm over it and 7 cm aside, pressed `force` N."""
    ctx = Context(info=BAXTER, params={}, environment=None)
    place = build_controller(Controller(name="place", params={"target": (0.10, 0.20, 0.0)}), "arm", ctx)
    period = BAXTER.control_period
    place.start(_arm(0.0, (0.17, 0.22, 0.08), 0.0))
    t = 0.0
    while t < seconds and place.status is Status.RUNNING:
        t += period
        place.update(_arm(t, (0.17, 0.22, 0.08), force if t > PRESSED_FROM else 0.0), period)
    return place, t


def test_a_place_pressing_on_what_blocks_it_on_the_way_ends_in_an_error() -> None:
    place, t = _place(111.0, 5.0)
    assert place.status is Status.ERROR, "the place pressed on for 5 s"
    assert t < PRESSED_FROM + 1.0
    assert "blocked" in place.reason and "111" in place.reason


def test_a_hand_held_up_without_pressing_is_not_blocked() -> None:
    place, _ = _place(0.0, 3.0)
    assert place.status is Status.RUNNING
