"""examples/unscrew_by_touch.xml finds the cap by touch: the closed hand (the SDH2's thumb, a
gripper's jaws), pointing down, feels its way down the believed bottle's axis onto the cap's
top, and the pinch comes down a known depth under where it touched, whatever the bottle's
height and whatever the hand (each hand's points are its description's). Nothing in the task is
the object's but its belief (what the campaign puts in it, `object_info`); the simulator's
cap says whether the pinch height is right."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from atd.model import load_task
from atd.runtime.session import Run, belief_scene
from atd.sim.library import get
from factories.registry import create
from translator import translate

TASK = Path(__file__).resolve().parents[2] / "examples" / "unscrew_by_touch.xml"
PINCH_UNDER_TOP = 0.002  # m: the TCP's height under the cap's top that unscrews the jam jar (examples/unscrew_fixture.xml)


def _pinch_down(robot: str, arm: str | None, engine: str) -> tuple[np.ndarray, float, object]:
    """The water bottle (205 mm, twice the jam jar the file's object is): the robot believes it
    from the library, as a campaign cell does; the run is stopped as the unscrew starts. The
    TCP then, the simulator's cap top and its state."""
    task, _ = load_task(TASK)
    bottle = get("water_bottle")
    task = task.model_copy(update={"object": bottle.object_info(0.12, 0.15)})
    factory = create(robot, arm)
    estd = translate(task, factory).estd
    scene = belief_scene(estd)
    run = Run(estd, factory, engine=engine, scene=replace(scene, object=bottle.in_fixture().realize(scene.object)))
    run.observers.append(lambda t: run.executor.machine.innermost().visit.path == "unscrew_cap"
                         and run.executor.stop("the pinch is down"))
    seen: dict = {}
    run.execute(afterwards=lambda robot: seen.update(tcp=robot.read().tcp, caps=robot.caps()))
    touched = [r for r in run.trace.records if r["type"] == "event" and r["state"] == "find_cap"]
    assert touched and touched[0]["event"] == "contact", touched
    cap = seen["caps"]["jar"]
    top = cap.pose[2, 3] + bottle.thread.cap_height / 2
    assert not cap.free and abs(top - 0.205) < 0.001  # the thread still holds it where it was
    return seen["tcp"], top, cap


def test_a_taller_bottles_cap_is_found_by_touch_and_the_pinch_comes_down_to_it() -> None:
    tcp, top, _ = _pinch_down("tombatossals", "left", "mujoco")
    assert abs(tcp[2, 3] - (top - PINCH_UNDER_TOP)) < 0.003, (tcp[2, 3], top)
    assert np.hypot(*(tcp[:2, 3] - (0.12 + 0.019, 0.15))) < 0.004  # the pinch centre (19 mm off) on the axis


def test_a_gripper_finds_the_same_cap_with_its_closed_jaws_and_grips_it_by_its_own_depth() -> None:
    """The same task on the Melfa (PyBullet, whose cap is as stiff as its bottle): the closed
    jaws touch the cap's top, and the open jaws come down around it, centred on its axis,
    their tips (23.8 mm under the TCP, its description's) 18 mm under the top, where the task
    puts any hand's fingertips: the whole 17 mm cap between the pads, the tips clear of the
    bottle's shoulder (the 12 mm neck under the cap)."""
    tcp, top, _ = _pinch_down("melfa", None, "pybullet")
    tips = tcp[2, 3] - create("melfa").robot.hand_reach("open")
    assert abs(tips - (top - 0.018)) < 0.003, (tips, top)
    assert np.hypot(*(tcp[:2, 3] - (0.12, 0.15))) < 0.004
