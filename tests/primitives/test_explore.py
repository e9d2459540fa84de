"""The explore primitive (thesis Table 3.1): down until the hand feels the object's top or the
box's floor, and where it felt it; nothing within its distance is an error, and so is an arm
that stops short without a contact; a pad's contact counts as the wrist's does."""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import numpy as np
import pytest

from atd.model.vocabulary import EventType
from primitives.arm.explore import Explore
from primitives.arm.move import EASE_OFF
from primitives.base import Context, Status
from primitives.robot import Readings
from primitives.values import Contact
from tests.primitives.box_worlds import CORNER, FLOOR, MELFA_REACH, box_world, cube
from tests.primitives.conftest import Stage, events, execute, leaf, machine, melfa, pushed_still, use

DOWN = (0.0, 0.0, -1.0)


def _over_then_down(xy: tuple[float, float], **explore) -> tuple:
    """Move over `xy` with the jaws closed (so the fingertips, not the palm between open jaws,
    touch a small object first), then explore down."""
    closed = use("hand_shape", shape="closed")
    return (Stage(use("cartesian_move", target=(*xy, 0.16)), closed, leaf("arm_done")),
            Stage(use("explore", direction=DOWN, writes="touched", **explore), closed, leaf("arm_done")))


@pytest.mark.parametrize("engine", ["mujoco", "pybullet"])
def test_explore_stops_on_the_object_top_and_on_the_floor_and_says_where(engine: str) -> None:
    robot = box_world(cube("block", CORNER), engine=engine)
    top = robot.object_poses()["block"][2, 3] + 0.025
    for xy, surface in ((CORNER, top), ((0.13, 0.12), FLOOR)):
        # written where the closed jaws' tips touched (`hand_point`: MELFA_REACH under the TCP)
        outcome, executor = execute(machine(*_over_then_down(xy, hand_point=(0.0, 0.0, MELFA_REACH))), robot)
        assert outcome.succeeded, outcome.summary
        touched = executor.machine.base.memory["touched"]
        assert isinstance(touched, Contact) and touched.sensor == "wrist"
        assert abs(touched.point[2] - surface) < 0.003  # the fingertips' height, within 3 mm
        assert np.linalg.norm(touched.point[:2] - xy) < 0.003  # straight down, not pushed aside
        assert "contact after" in events(executor)[-1]["conditions"][0]["reason"]
    robot.close()


def test_nothing_within_the_distance_is_an_error_and_writes_nothing() -> None:
    robot = box_world()
    stages = _over_then_down((0.13, 0.12), max_distance=0.05)
    estd = machine(stages[0], dataclasses.replace(stages[1], until=leaf("arm_done")),
                   failures={"s1": (EventType.ERROR, leaf("arm_error"))})
    outcome, executor = execute(estd, robot)
    assert not outcome.succeeded and outcome.end_state == "failed"
    assert events(executor)[-1]["conditions"][0]["reason"] == "nothing within 0.05 m"
    assert "touched" not in executor.machine.base.memory
    assert robot.read().tcp[2, 3] == pytest.approx(0.11, abs=0.003)  # went its 5 cm and stopped there
    robot.close()


def test_a_pad_s_force_over_its_start_is_a_contact_and_named() -> None:
    robot = melfa()
    ctx = Context(info=robot.info, params={"direction": DOWN, "speed": 0.04, "force_threshold": 3.0,
                                           "max_distance": 0.3, "filter_time": 0.0, "writes": "touched"})
    explore = Explore(ctx)
    held = dataclasses.replace(robot.read(), pad_force=np.array([4.0, 0.0]))  # a grip's force, tared at the start
    explore.start(held)
    explore.update(dataclasses.replace(held, pad_force=np.array([6.5, 0.0])), 0.005)
    assert explore.status is Status.RUNNING  # 6.5 N, but only 2.5 N more than it held at the start
    explore.update(dataclasses.replace(held, pad_force=np.array([7.5, 0.0])), 0.005)
    pad = robot.info.hand.pads[0].name
    assert ctx.memory["touched"].sensor == pad and ctx.memory["touched"].force == pytest.approx(3.5)
    assert explore.status is Status.RUNNING  # easing off what it touched
    eased = held.tcp.copy()
    eased[2, 3] += EASE_OFF
    explore.update(dataclasses.replace(held, tcp=eased), 0.005)
    assert explore.status is Status.DONE  # done once off it: the next motion starts from rest
    robot.close()


def _rise(robot) -> tuple[Explore, Callable[[float, tuple[float, float, float]], Readings]]:
    """free_one's rise (an explore up, feeling 150 N) on the Melfa, and its readings at a time
    with a force (N, world frame) on the hand beyond what the believed empty hand reads."""
    ctx = Context(info=robot.info, params={"direction": (0.0, 0.0, 1.0), "speed": 0.15, "force_threshold": 150.0,
                                           "max_distance": 0.15, "filter_time": 0.0})
    return Explore(ctx), pushed_still(robot)


def test_a_press_the_hand_rises_off_is_not_a_contact_as_it_eases_but_one_from_above_is() -> None:
    """free_one's rise started on the Baxter's wrist pressed at 200 N by the slides before it
    (seed 77123, docs/empty-the-box.md): against the start's tare the press easing read as a
    151.6 N contact, and the run ended `stuck`."""
    robot = melfa()
    explore, pushed = _rise(robot)
    dt = 0.005
    explore.start(pushed(0.0, (60.0, 0.0, 200.0)))  # the object below pushes the hand up and aside
    for tick, up in enumerate(np.linspace(200.0, 0.0, 101)):  # eased in 0.5 s, as the rise leaves it
        explore.update(pushed(tick * dt, (0.3 * up, 0.0, up)), dt)
        assert explore.status is Status.RUNNING and explore.found is None, up
    for tick, down in enumerate(np.linspace(0.0, 155.0, 32), start=101):  # then something above pushes it down
        explore.update(pushed(tick * dt, (0.0, 0.0, -down)), dt)
    assert explore.found is not None and explore.found.sensor == "wrist" and explore.found.force >= 150.0
    robot.close()


def test_an_arm_that_stops_short_without_a_contact_ends_in_error_naming_the_joint() -> None:
    """An explore up whose arm cannot go on (j5 held at its lower limit, the hand where it
    started) waits 2 s for progress, then gives up saying which joint stops it: the task goes
    on to its no_contact edge rather than wait for ever."""
    robot = melfa()
    info = robot.info
    explore = Explore(Context(info=info, params={"direction": (0.0, 0.0, 1.0), "speed": 0.04, "force_threshold": 3.0,
                                                 "max_distance": 0.15, "filter_time": 0.0}))
    start = robot.read()
    q = start.arm_q.copy()
    q[4] = info.arm_lower[4]
    stuck = dataclasses.replace(start, arm_q=q)
    explore.start(stuck)
    for tick in range(1, 401):  # 2 s
        explore.update(dataclasses.replace(stuck, time=start.time + tick * 0.005), 0.005)
    assert explore.status is Status.RUNNING
    for tick in range(401, 421):
        explore.update(dataclasses.replace(stuck, time=start.time + tick * 0.005), 0.005)
    assert explore.status is Status.ERROR and explore.found is None
    assert explore.reason.startswith("no contact, and no progress for 2 s 15.0 cm short of 0.15 m")
    assert explore.reason.endswith(f"joint 'j5' at its lower limit ({info.arm_lower[4]:.2f})")
    robot.close()


def test_a_hold_against_the_rise_letting_go_is_not_a_contact_but_one_met_after_it_is() -> None:
    """free_one's rise on the Barrett (seed 30100, docs/empty-the-box.md) started with a finger
    held under something, the hand pushed 94 N down and 124 N across, and sprang free within a
    tick: against its tare the release read as a 157 N contact, the rise stopped 1 cm up and
    left the hand in the box, where `aside` met an object."""
    robot = melfa()
    explore, pushed = _rise(robot)
    held = (-116.0, -45.0, -94.0)  # N on the hand, world frame
    dt = 0.005
    explore.start(pushed(0.0, held))
    for tick in range(1, 40):
        explore.update(pushed(tick * dt, held if tick < 20 else (0.0, 0.0, 0.0)), dt)  # free at 0.1 s
        assert explore.status is Status.RUNNING and explore.found is None, tick
    explore.update(pushed(40 * dt, (0.0, 0.0, -155.0)), dt)  # then something above pushes it down
    assert explore.found is not None and explore.found.sensor == "wrist" and explore.found.force >= 150.0
    robot.close()
