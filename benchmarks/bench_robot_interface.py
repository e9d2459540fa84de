"""What the robot interface costs over bare engine stepping, per robot and engine.

For each robot model and engine, the same simulated world is advanced twice for the same
simulated time: by the engine alone (the physics steps of each control tick, with the
servo references left as they are), and through the robot interface as the executor drives
it each 5 ms tick: a velocity command, the hand command repeated, `step()`, and a `read()`
whose every field (every sensor) is looked at. Both run while the hand holds the 5 cm test
box in the air, where contacts make sensing dearest. Prints steps per second,
the real-time factor through the interface and the overhead ratio (target: at most 1.25).
A third loop gives the floor under that ratio: the engine handed its servo references and
every true reading fetched, with none of the interface's own work (reference generator,
sensor models, taxel images, the snapshot).

    python benchmarks/bench_robot_interface.py [--seconds 2] [--repeat 3] [--robot melfa]
"""

from __future__ import annotations

import argparse
import sys
import time
from dataclasses import fields
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from atd.sim import ENGINES, load_description, make_robot, variants  # noqa: E402
from atd.sim.selftest import close_on_box, move_tcp, pose  # noqa: E402
from atd.sim.simrobot import SimRobot  # noqa: E402
from primitives.robot import HandMode, Readings  # noqa: E402

FIELDS = tuple(f.name for f in fields(Readings))
#: What the loops time with: wall time by default; `use_cpu_time` switches to this thread's
#: CPU time, which a machine loaded by other processes leaves nearly as a quiet one reads.
clock = time.perf_counter


def use_cpu_time() -> None:
    """Time the loops (and `bench_tick`'s runs) in this thread's CPU time rather than wall time."""
    global clock
    clock = time.thread_time


def holding(robot: SimRobot) -> tuple[np.ndarray, list[HandMode]]:
    """Grip the test box as the self-test does and lift it 5 cm; returns the hand command."""
    orientation = robot.read().tcp[:3, :3]
    box = robot.object_pose()[:3, 3]
    hand = close_on_box(robot, orientation, robot.step)
    move_tcp(robot, pose(orientation, box + (0, 0, 0.05)), robot.step, speed=0.1)
    return hand


def bare_loop(robot: SimRobot, ticks: int) -> float:
    """Seconds for the engine alone to run `ticks` control periods: its physics step with
    the robot's actuator model (inside `mj_step` in MuJoCo; in PyBullet partly Python: the
    servo force limits and the torques of gravity compensation and self-locking drives)."""
    start = clock()
    for _ in range(ticks):
        robot._advance()
    return clock() - start


def raw_loop(robot: SimRobot, ticks: int) -> float:
    """Seconds to run `ticks` control periods doing only what any interface to this engine
    must: set the arm's servo references, step, and fetch each true reading once."""
    hold, zero = robot.read().arm_q.copy(), np.zeros(robot.info.arm_dof)
    start = clock()
    for _ in range(ticks):
        robot._apply_arm(hold, zero)
        robot._advance()
        robot._joint_state(), robot._tcp(), robot._wrench(), robot._pad_contacts()
        if robot.info.has_range:
            robot._range()
    return clock() - start


def interface_loop(robot: SimRobot, ticks: int, hand: tuple[np.ndarray, list[HandMode]]) -> float:
    """Seconds to run `ticks` control periods through the interface, reading everything:
    each field of the snapshot is fetched, so a reading worked out lazily would be paid here."""
    still = np.zeros(robot.info.arm_dof)
    values, modes = hand
    start = clock()
    for _ in range(ticks):
        robot.command_arm_velocity(still)
        robot.command_hand(values, modes)
        robot.step()
        readings = robot.read()
        touched = [getattr(readings, name) for name in FIELDS]
        touched += readings.taxels.values()
    return clock() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seconds", type=float, default=2.0, help="simulated seconds per measurement")
    parser.add_argument("--repeat", type=int, default=3, help="measurements per loop; the fastest counts")
    parser.add_argument("--robot", help="only this robot (default: every robot and arm)")
    args = parser.parse_args()

    print(f"{'robot':<20} {'engine':<9} {'bare steps/s':>13} {'interface steps/s':>18} {'x real time':>12} "
          f"{'overhead':>9} {'raw floor':>10}")
    worst = 0.0
    for robot_name, arm in variants(args.robot):
        description = load_description(robot_name, arm)
        for engine in ENGINES:
            robot = make_robot(description, engine=engine)
            try:
                hand = holding(robot)
                ticks = round(args.seconds / robot.info.control_period)
                steps = ticks * robot.substeps
                # Interleaved, so that the loops see the same states of the held box.
                times = [(bare_loop(robot, ticks), interface_loop(robot, ticks, hand), raw_loop(robot, ticks))
                         for _ in range(args.repeat)]
                bare, through, raw = (min(t[k] for t in times) for k in range(3))
            finally:
                robot.close()
            ratio = through / bare
            worst = max(worst, ratio)
            print(
                f"{description.label:<20} {engine:<9} {steps / bare:>13,.0f} {steps / through:>18,.0f} "
                f"{args.seconds / through:>12.1f} {ratio:>9.2f} {raw / bare:>10.2f}"
            )
    print(f"worst overhead ratio {worst:.2f} (target <= 1.25)")


if __name__ == "__main__":
    main()
