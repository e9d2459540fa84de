"""The judge: what happened to the object, from the simulator's ground truth.

The task's own verdict is the robot's opinion, formed from its sensors; the judge reads
only the simulator's true object and hand poses, so a trial records both and their
disagreement shows an event that claimed what did not happen.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Sequence

import numpy as np

from atd.model.frames import rotation_angle
from atd.sim.simrobot import SimRobot

#: Thesis 3.4.1: the object is lifted and "does not move in the hand".
MIN_LIFT = 0.05  # m above where it started
MAX_SLIP = 0.01  # m of motion relative to the hand over the hold
MAX_TURN = 5.0  # degrees of rotation relative to the hand over the hold
HOLD = 2.0  # s the hand holds still while the object is watched
#: A pick-and-place: the object rests within this distance (horizontally) of the target.
PLACE_TOLERANCE = 0.02  # m
SETTLE = 1.0  # s the world is left alone before the resting place is read
RESTING = 0.01  # m: the object's centre at most this far above its resting height


@dataclass
class Verdict:
    succeeded: bool
    reason: str
    measurements: dict[str, float] = field(default_factory=dict)


class LiftJudge:
    """Grasp and lift: the object rose at least 5 cm and stayed put in the hand (at most
    1 cm and 5° relative to it) while the hand held still for 2 s."""

    def __init__(self, robot: SimRobot) -> None:
        self.start = robot.object_pose()
        self.verdict: Verdict | None = None

    def __call__(self, robot: SimRobot) -> None:
        before = np.linalg.inv(robot.true_tcp()) @ robot.object_pose()
        robot.hold_still(HOLD)
        end = robot.object_pose()
        after = np.linalg.inv(robot.true_tcp()) @ end
        lift = float(end[2, 3] - self.start[2, 3])
        slip = float(np.linalg.norm(after[:3, 3] - before[:3, 3]))
        turn = rotation_angle(after[:3, :3] @ before[:3, :3].T)
        m = {"lift": lift, "slip": slip, "turn": turn}
        if lift < MIN_LIFT:
            self.verdict = Verdict(False, f"not lifted: {lift * 100:.1f} cm above its start, "
                                          f"{MIN_LIFT * 100:g} cm needed", m)
        elif slip > MAX_SLIP or turn > MAX_TURN:
            self.verdict = Verdict(False, f"moved in the hand during the {HOLD:g} s hold: {slip * 1000:.1f} mm, "
                                          f"{turn:.1f}° (at most {MAX_SLIP * 1000:g} mm, {MAX_TURN:g}°)", m)
        else:
            self.verdict = Verdict(True, f"lifted {lift * 100:.1f} cm, held still: {slip * 1000:.1f} mm, "
                                         f"{turn:.1f}° in the hand over {HOLD:g} s", m)


class PlaceJudge:
    """Pick and place: the object rests on the table within 2 cm of the target."""

    def __init__(self, robot: SimRobot, target: tuple[float, float, float]) -> None:
        self.target = np.asarray(target, float)
        self.rest_height = float(robot.object_pose()[2, 3])  # it starts resting on the table
        self.verdict: Verdict | None = None

    def __call__(self, robot: SimRobot) -> None:
        robot.hold_still(SETTLE)
        where = robot.object_pose()[:3, 3]
        off = float(np.hypot(*(where[:2] - self.target[:2])))
        height = float(where[2] - self.rest_height)
        m = {"distance": off, "height": height}
        if height > RESTING:
            self.verdict = Verdict(False, f"not resting on the table: {height * 100:.1f} cm above its "
                                          f"resting height", m)
        elif off > PLACE_TOLERANCE:
            self.verdict = Verdict(False, f"rests {off * 100:.1f} cm from the target "
                                          f"(at most {PLACE_TOLERANCE * 100:g} cm)", m)
        else:
            self.verdict = Verdict(True, f"rests {off * 100:.1f} cm from the target", m)



#: s of simulated time between two looks of a box judge that may stop the run
LOOK_EVERY = 1.0


class BoxJudge:
    """Emptying a box (thesis 3.4.3): the box is empty at the end, every object that was in
    it now outside. A task that reached success with an object left made a false "empty"
    (the trial's false success). With `stop`, it also stops a run (the thesis's supervisor)
    as soon as the box is empty: for a task that cannot know it (random blind)."""

    def __init__(self, robot: SimRobot, container: str, stop: Callable[[str], None] | None = None) -> None:
        self.robot = robot
        self.container = container
        self.start = robot.objects_inside(container)
        self.stop = stop
        self.next_look = LOOK_EVERY
        self.looks: list[tuple[float, int]] = [(0.0, len(self.start))]  # (s, objects in the box)
        self.verdict: Verdict | None = None

    def watch(self, sim_time: float) -> None:
        """An observer of the run: every LOOK_EVERY s, count what is in the box (for
        `by_remaining`), and stop the run once it is empty when told to."""
        if sim_time < self.next_look:
            return
        self.next_look = sim_time + LOOK_EVERY
        self.looks.append((sim_time, len(self.robot.objects_inside(self.container))))
        if self.stop is not None and not self.looks[-1][1]:
            self.stop(f"the judge sees '{self.container}' empty")

    def by_remaining(self, attempts: Sequence[float]) -> dict[str, float]:
        """How many of the grasp attempts (the times they began) were made with k objects
        in the box (the latest look before each), as `attempts_with_k_left` (thesis Fig. 3.27)."""
        counts: dict[str, float] = {}
        for began in attempts:
            left = next(n for t, n in reversed(self.looks) if t <= began)
            counts[f"attempts_with_{left}_left"] = counts.get(f"attempts_with_{left}_left", 0.0) + 1.0
        return counts

    def __call__(self, robot: SimRobot) -> None:
        robot.hold_still(SETTLE)
        left = robot.objects_inside(self.container)
        m = {"objects": float(len(self.start)), "remaining": float(len(left))}
        if left:
            self.verdict = Verdict(False, f"{len(left)} of {len(self.start)} objects left in '{self.container}': "
                                          f"{', '.join(left)}", m)
        else:
            self.verdict = Verdict(True, f"'{self.container}' emptied of {len(self.start)} objects", m)


#: Where a free cap rests (`atd.sim.thread.Rest`), in words.
RESTS = {"table": "on the table", "bottle": "back on its bottle", "held": "held by the robot",
         "elsewhere": "neither on the table nor held (on another object, or falling)"}


class CapJudge:
    """Unscrewing a cap and putting it on the table (thesis 3.4.2): after the world is left
    alone, the simulator says whether the cap is off its thread ("cap unscrewed", whatever
    the task said) and where it rests. The trial succeeded when the task said so and the cap
    is free and resting on the table (the thesis: "removes the cap from the object and places
    it on the table by itself"); a task that says so of a cap elsewhere made a false success."""

    def __init__(self, robot: SimRobot) -> None:
        caps = robot.caps()
        if len(caps) != 1:
            raise ValueError(f"the cap judge needs one screw-capped object, the world has {len(caps)}")
        self.name = next(iter(caps))
        self.free = False
        self.rests = "bottle"
        self.turns = 0.0

    def __call__(self, robot: SimRobot) -> None:
        robot.hold_still(SETTLE)
        cap = robot.caps()[self.name]
        self.free, self.rests, self.turns = cap.free, cap.rests, cap.turns

    def verdict(self, task_succeeded: bool) -> Verdict:
        """The verdict, given what the task said; `cap_free` and `cap_on_table` are the truth alone."""
        on_table = self.free and self.rests == "table"
        m = {"cap_free": float(self.free), "cap_on_table": float(on_table), "cap_turns": self.turns}
        where = f"off its thread, {RESTS[self.rests]}" if self.free else f"still on its thread, turned {self.turns:.2f} turns"
        if not on_table:
            return Verdict(False, f"the cap of '{self.name}' is {where}", m)
        if not task_succeeded:
            return Verdict(False, f"the cap of '{self.name}' is {where}, but the task did not say it put it there", m)
        return Verdict(True, f"the cap of '{self.name}' is {where}", m)
