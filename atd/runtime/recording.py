"""A run's signals, recorded per tick into MCAP: what the robot's sensors read, what the
arbitrator commanded, where the task was, and the simulator's ground truth beside them.

MCAP with JSON schemas is what Foxglove and PlotJuggler open as is (and what ROS 2 bags
are), so a roboticist can plot pad forces against the wrist force with the tools they
already use. Times are simulated time, in nanoseconds. The channel `/truth` carries the
simulator's ground truth (channel metadata `ground_truth: true`): no primitive sees it.
Foxglove's 3D panel draws the robot, the objects and the table from `/truth/tf` and
`/truth/scene` (atd/runtime/recording_scene.py), its Image panel the depth camera's pictures
(atd/runtime/recording_images.py).

On the control loop a sample is only its numbers copied into a row of floats; rows go in
blocks to a writer process, which builds the messages and the file on the other core
(atd/runtime/recording_format.py, atd/runtime/recording_writer.py): that work costs two to
three times what the copy does, and the control loop no longer waits for it.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from atd.runtime.executor import Executor, Outcome
from atd.runtime.recording_format import DEFAULT_RATE, RECORDING_FORMAT, Layout, Sample
from atd.runtime.recording_scene import Arm, frames_of
from atd.runtime.recording_writer import RecordingWriter
from atd.runtime.trace import Trace
from atd.sim.simrobot import SimRobot
from primitives.robot import DepthImage

__all__ = ["DEFAULT_RATE", "RECORDING_FORMAT", "Recording"]

BLOCK = 25  # samples per block sent: about 50 KB


class Recording:
    """An observer of the executor: every `1/rate` s of simulated time (every tick when
    `rate` is None) it takes one sample; trace records go as they happen. `finish` writes
    the file; `abandon` (a run that did not end) leaves none."""

    def __init__(self, path: Path, robot: SimRobot, executor: Executor, trace: Trace,
                 objects: tuple[str, ...], rate: float | None = DEFAULT_RATE, info: dict[str, str] | None = None,
                 attachments: dict[str, bytes] | None = None) -> None:
        self.robot, self.executor, self.trace = robot, executor, trace
        self.period = 0.0 if rate is None else 1.0 / rate
        self.next = 0.0
        hand = robot.info.hand
        arms = tuple(Arm("" if k == 0 else f"{arm.description.arm or k}/", arm.description,
                         (*arm.description.arm_joints, *arm.hand_joints)) for k, arm in enumerate(robot.arms))
        self.layout = Layout(len(robot.info.arm_joints), len(hand.dofs), tuple((p.name, p.taxels) for p in hand.pads),
                             objects, sum(len(arm.joints) for arm in arms))
        self.block = np.empty((BLOCK, self.layout.width))
        self.samples: list[Sample] = []
        self.traces: list[tuple[int, dict[str, Any]]] = []
        self.traced = 0  # trace records sent so far
        self.visit: object = None
        self.state: tuple[str, str] = ("", "")
        self.hand_modes: tuple | None = None
        self.modes_sent: list[str] | None = None
        self.writer = RecordingWriter(path)
        self.writer.send(("start", self.layout, {"arm_joints": " ".join(robot.info.arm_joints),
                                                 "hand_dofs": " ".join(hand.dofs), "wrench_frame": "hand"},
                          info or {}, attachments or {}))
        self.writer.send(("scene", frames_of(arms, robot.scene)))
        robot.on_capture = self._picture

    def __call__(self, sim_time: float) -> None:
        if len(self.trace.records) > self.traced:
            self._take_trace()
        if sim_time + 1e-9 < self.next:
            return
        self.next = sim_time + self.period
        command = self.executor.command
        if command is not None and command.hand_modes != self.hand_modes:
            self.hand_modes = command.hand_modes
            self.modes_sent = [str(m) for m in command.hand_modes]
        visit = self.executor.machine.innermost().visit
        if visit is not self.visit:
            self.visit, self.state = visit, (visit.path, visit.atd)
        row = self.layout.row(sim_time, self.robot.read(), command, self.robot.true_tcp(),
                              list(self.robot.recorded_poses().values()), self.robot.true_joints())
        np.concatenate(row, out=self.block[len(self.samples)])
        pads, points, forces = self.robot.true_pad_contacts()
        self.samples.append((self.state, self.modes_sent, (pads.tolist(), points.tolist(), forces.tolist())))
        if len(self.samples) == BLOCK:
            self._send()

    def _picture(self, image: DepthImage) -> None:
        """A depth picture a state took: to the writer now (it is no tick's reading)."""
        self.writer.send(("image", image))

    def _take_trace(self) -> None:
        self.traces += [(len(self.samples), record) for record in self.trace.records[self.traced:]]
        self.traced = len(self.trace.records)

    def _send(self) -> None:
        self.writer.send(("rows", self.block[:len(self.samples)], self.samples, self.traces))
        self.samples, self.traces = [], []

    def finish(self, outcome: Outcome) -> None:
        """Write the end of the run and the file, whole (OutputError when it cannot be)."""
        self._take_trace()
        self._send()
        self.robot.on_capture = None
        self.writer.finish({"succeeded": str(outcome.succeeded).lower(), "summary": outcome.summary,
                            "end_state": outcome.end_state or "", "sim_time": f"{outcome.sim_time:.6f}"})

    def abandon(self) -> None:
        """The run did not end (an exception, Ctrl-C): stop the writer, leave no file. (Once
        the file is written, nothing.)"""
        self.robot.on_capture = None
        self.writer.abandon()
