"""examples/unscrew_by_touch.xml finds the cap by touch: the SDH2's thumb, pointing down,
feels its way down the believed bottle's axis onto the cap's top, and the pinch comes down
a known depth under where it touched, whatever the bottle's height. Nothing in the task is
the object's but its belief (what the campaign puts in it, `object_info`); the simulator's
cap says whether the pinch height is right and whether the pinch turns it."""

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
THUMB_REACH = 0.021  # m: the SDH2's thumb tip under the TCP in its push posture: where the touch meets the cap's top
PINCH_DEPTH = 0.022  # m: the task's pinch target under the TCP's touch (around_cap's offset)
ARRIVED = 0.003  # m: its guarded move ends this near its target (the moves' tolerance)
TWISTED = 3.0  # s of the unscrew: the pinch presses 10 N within 1 s, a 30-degree twist takes about 1 s more


def test_a_taller_bottles_cap_is_found_by_touch_and_the_pinch_comes_down_to_it_and_turns_it() -> None:
    """The water bottle (205 mm, twice the jam jar the file's object is; a 30 mm cap of 2.5 g):
    the robot believes it from the library, as a campaign cell does; the run is stopped
    TWISTED s into the unscrew, by when the pinch has pressed the cap and twisted it once."""
    task, _ = load_task(TASK)
    bottle = get("water_bottle")
    task = task.model_copy(update={"object": bottle.object_info(0.12, 0.15)})
    factory = create("tombatossals", "left")
    estd = translate(task, factory).estd
    scene = belief_scene(estd)
    run = Run(estd, factory, engine="mujoco", scene=replace(scene, object=bottle.in_fixture().realize(scene.object)))
    seen: dict = {}

    def watch(now: float) -> None:
        if run.executor.machine.innermost().visit.path != "unscrew_cap":
            return
        start = seen.setdefault("start", (now, run.robot.read().tcp, run.robot.caps()["jar"]))
        if now - start[0] >= TWISTED:
            run.executor.stop("the first twist is made")

    run.observers.append(watch)
    run.execute(afterwards=lambda robot: seen.update(caps=robot.caps()))
    touched = [r for r in run.trace.records if r["type"] == "event" and r["state"] == "find_cap"]
    assert touched and touched[0]["event"] == "contact", touched
    _, tcp, cap = seen["start"]
    top = cap.pose[2, 3] + bottle.thread.cap_height / 2
    assert not cap.free and abs(top - 0.205) < 0.001  # the thread still holds it where it was
    assert 0.0 <= tcp[2, 3] - (top + THUMB_REACH - PINCH_DEPTH) <= ARRIVED + 0.001, (tcp[2, 3], top)
    assert np.hypot(*(tcp[:2, 3] - (0.12 + 0.019, 0.15))) < 0.004  # the pinch centre (19 mm off) on the axis
    turned = seen["caps"]["jar"].turned
    assert turned > 0.4 and not seen["caps"]["jar"].free, turned  # most of one 30-degree twist (0.52 rad)
