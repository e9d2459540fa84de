"""A box turned a quarter turn (issue 33): the Melfa's jaws, 68 mm open, come down at its home
yaw across the 7 cm block's length and cannot close on it; turned to the box as the task
believes it stands, they close across its 4 cm side and lift it."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from tests.primitives.conftest import EXAMPLES, run_example

# The library's beech block (70 x 40 x 45 mm, 90 g), its length along the world y.
TURNED_BOX = """<object>
    <pose>0 -1 0 0.10  1 0 0 0.0  0 0 1 0.0225  0 0 0 1</pose>
    <weight>0.09</weight>
    <friction>0.6</friction>
    <class>box</class>
    <size>0.07 0.04 0.045</size>
  </object>"""


def test_the_jaws_come_down_across_a_turned_box_and_lift_it(tmp_path: Path) -> None:
    text = (EXAMPLES / "grasp_and_lift.xml").read_text()
    task = tmp_path / "turned_box.xml"
    task.write_text(text[:text.index("<object>")] + TURNED_BOX + text[text.index("</object>") + len("</object>"):])
    closing: list[np.ndarray] = []  # the jaws' closing axis (the TCP's y) while the grasp closes

    def watch(robot, path: str, time: float) -> None:
        if path.endswith("grasp_object"):
            closing.append(robot.true_tcp()[:3, 1].copy())

    outcome, _, sim = run_example(task, watch)
    assert outcome.succeeded, outcome.summary
    assert sim.object_pose()[2, 3] > 0.0225 + 0.05  # lifted, as the simulator has it
    assert closing and abs(float(closing[-1][0])) > math.cos(math.radians(5.0))  # across the box's 4 cm side
