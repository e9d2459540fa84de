"""How the screw caps of the object library behave (docs/objects.md): per object and engine,
each bottle or jar held in its fixture beside the parked Melfa,

- how far its cap turns in 1 s under 0.8 x its thread's torque (it should not),
- how far a 5 N pull lifts its closed cap in 0.3 s (the thread should hold it),
- under 1.2 x the torque: the simulated time until the thread lets the cap go, the turns
  then, the rise at the last threaded tick against pitch x turns, and the worst gap
  between rise and pitch x turns on the way,
- the wall time of a control tick with the object standing free, against the library's
  plain cylinder,
- and a robot's own unscrewing: the Melfa pinching the water bottle's cap (10 N a pad, the
  bottle cut to 144 mm so the cap stands within its pads) and turning its wrist 1 rad
  counter-clockwise seen from above: how far the cap turned and rose.

    python benchmarks/bench_screw_caps.py [--engine mujoco pybullet]

Wall times move with the machine's load; the rest does not.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from atd.sim import ENGINES, load_description, make_robot  # noqa: E402
from atd.sim.library import LibraryObject, get, library  # noqa: E402
from atd.sim.scene import Scene  # noqa: E402
from atd.sim.simrobot import SimRobot  # noqa: E402
from primitives.robot import HandMode  # noqa: E402

PLACE = (0.15, 0.2)  # beside the parked hand
TICKS = 500


def _scene(found: LibraryObject) -> Scene:
    pose = np.eye(4)
    pose[:3, 3] = (*PLACE, found.size[-1] / 2)
    return Scene(found.body(found.name, pose))


def _rise(robot: SimRobot, name: str) -> float:
    return float(robot.caps()[name].pose[2, 3])


def _measure(found: LibraryObject, engine: str) -> str:
    melfa, name, thread = load_description("melfa"), found.name, found.thread
    assert thread is not None
    robot = make_robot(melfa, _scene(found.in_fixture()), engine)
    robot.push_cap(name, 0.8 * thread.torque)
    robot.hold_still(1.0)
    below = robot.caps()[name].turned
    robot.close()
    robot = make_robot(melfa, _scene(found.in_fixture()), engine)
    robot.hold_still(0.1)
    closed = _rise(robot, name)
    robot.push_cap(name, force=(0.0, 0.0, 5.0))
    robot.hold_still(0.3)
    pulled = _rise(robot, name) - closed
    robot.close()
    robot = make_robot(melfa, _scene(found.in_fixture()), engine)
    robot.hold_still(0.1)
    closed, start = _rise(robot, name), robot.read().time
    robot.push_cap(name, 1.2 * thread.torque)
    seen = []
    while not robot.caps()[name].free and robot.read().time - start < 5.0:
        robot.step()
        cap = robot.caps()[name]
        seen.append((cap.turns, cap.pose[2, 3] - closed))
    took = robot.read().time - start
    robot.close()
    turns, rise = np.array(seen).T
    worst = np.abs(rise[:-1] - thread.pitch * turns[:-1]).max()
    robot = make_robot(melfa, _scene(found), engine)
    robot.hold_still(0.1)
    began = time.perf_counter()
    for _ in range(TICKS):
        robot.step()
    tick = (time.perf_counter() - began) / TICKS
    robot.close()
    return (f"| `{name}` | {engine} | {below:.4f} rad | {pulled * 1e3:.2f} mm | {took:.2f} s | {turns[-1]:.3f} | "
            f"{rise[-2] * 1e3:.2f} / {thread.travel * 1e3:.2f} mm | {worst * 1e3:.2f} mm | {tick * 1e3:.2f} ms |")


def _tick(engine: str) -> float:
    robot = make_robot(load_description("melfa"), _scene(get("cylinder")), engine)
    robot.hold_still(0.1)
    began = time.perf_counter()
    for _ in range(TICKS):
        robot.step()
    robot.close()
    return (time.perf_counter() - began) / TICKS


def _pinch_and_turn(engine: str) -> str:
    height = 0.144
    pose = np.eye(4)
    pose[:3, 3] = (0.125, 0.0, height / 2)
    found = get("water_bottle").in_fixture()
    bottle = dataclasses.replace(found.body("bottle", pose), size=(0.032, height))
    robot = make_robot(load_description("melfa"), Scene(bottle), engine)
    hand = robot.info.hand
    robot.command_hand(hand.closing * 10.0, [HandMode.FORCE] * len(hand.dofs))
    robot.hold_still(1.0)
    pads = robot.read().pad_force
    turn = np.zeros(len(robot.info.arm_joints))
    turn[-1] = -0.5
    robot.command_arm_velocity(turn)
    for _ in range(round(2.0 / robot.info.control_period)):
        robot.step()
    cap = robot.caps()["bottle"]
    rise = cap.pose[2, 3] - found.thread.closed_cap(pose, height)[2, 3]
    robot.close()
    return (f"{engine}: pads {pads[0]:.1f} and {pads[1]:.1f} N; wrist turned 1 rad, the cap {cap.turned:.3f} rad, "
            f"rising {rise * 1e3:.3f} mm (pitch x turns: {found.thread.pitch * cap.turned / (2 * math.pi) * 1e3:.3f} mm)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--engine", nargs="+", choices=ENGINES, default=list(ENGINES))
    engines = parser.parse_args().engine
    print("| object | engine | 0.8 x torque, 1 s: turned | 5 N pull on the closed cap: rise | 1.2 x torque: free after "
          "| turns | rise at the end / pitch x turns | worst rise - pitch x turns | a tick (wall) |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for found in library().values():
        if found.thread is not None:
            for engine in engines:
                print(_measure(found, engine), flush=True)
    for engine in engines:
        print(f"| `cylinder` (no cap) | {engine} | | | | | | | {_tick(engine) * 1e3:.2f} ms |")
    for engine in engines:
        print(_pinch_and_turn(engine))


if __name__ == "__main__":
    main()
