"""examples/unscrew_by_touch.xml finds the cap by touch: the SDH2's thumb, pointing down,
feels its way down the believed bottle's axis onto the cap's top, and the pinch comes down
a known depth under where it touched, whatever the bottle's height. Nothing in the task is
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


def test_a_taller_bottles_cap_is_found_by_touch_and_the_pinch_comes_down_to_it() -> None:
    """The water bottle (205 mm, twice the jam jar the file's object is): the robot believes it
    from the library, as a campaign cell does; the run is stopped as the unscrew starts."""
    task, _ = load_task(TASK)
    bottle = get("water_bottle")
    task = task.model_copy(update={"object": bottle.object_info(0.12, 0.15)})
    factory = create("tombatossals", "left")
    estd = translate(task, factory).estd
    scene = belief_scene(estd)
    run = Run(estd, factory, engine="mujoco", scene=replace(scene, object=bottle.in_fixture().realize(scene.object)))
    run.observers.append(lambda t: run.executor.machine.innermost().visit.path == "unscrew_cap"
                         and run.executor.stop("the pinch is down"))
    seen: dict = {}
    run.execute(afterwards=lambda robot: seen.update(tcp=robot.read().tcp, caps=robot.caps()))
    touched = [r for r in run.trace.records if r["type"] == "event" and r["state"] == "find_cap"]
    assert touched and touched[0]["event"] == "contact", touched
    cap = seen["caps"]["jar"]
    top = cap.pose[2, 3] + bottle.thread.cap_height / 2
    assert not cap.free and abs(top - 0.205) < 0.001  # the thread still holds it where it was
    assert abs(seen["tcp"][2, 3] - (top - PINCH_UNDER_TOP)) < 0.003, (seen["tcp"][2, 3], top)
    assert np.hypot(*(seen["tcp"][:2, 3] - (0.12 + 0.019, 0.15))) < 0.004  # the pinch centre (19 mm off) on the axis
