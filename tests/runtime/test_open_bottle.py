"""The two-arm bottle task (thesis 3.4.2) on Tombatossals in MuJoCo, examples/open_bottle.xml:
the holder (the Barrett) grasps the jam jar from the side and holds it, upright, at the
vantage pose the task gives while the opener (the SDH2) finds the cap's top by touch and
unscrews it; the task says it opened the jar only where the simulator agrees (the cap off its
thread and on the table, the jar back standing on it); a robot without a second arm is
refused at the opener's role, in the file. Seeds and Baxter: docs/open-bottle.md."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from click.testing import CliRunner

from atd.cli import main
from atd.model import load_task
from atd.runtime.session import Run, world_scene
from factories.registry import create
from translator import translate

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
TASK, WORLD = EXAMPLES / "open_bottle.xml", EXAMPLES / "open_bottle.world.toml"
STANDING = (0.10, 0.0, 0.0525)  # the jar's centre on the table (the world file, the task's belief)
VANTAGE_RISE = 0.10  # m the task lifts the holder's hand from its grasp to the vantage pose
UPRIGHT = np.cos(np.radians(5.0))  # the jar's axis within 5 degrees of vertical


def test_the_holder_keeps_the_jar_up_while_the_opener_unscrews_its_cap_and_both_put_theirs_down() -> None:
    task, _ = load_task(TASK)
    factory = create("tombatossals")
    estd = translate(task, factory).estd
    assert estd.roles == {"holder": "right", "opener": "left"}
    run = Run(estd, factory, engine="mujoco", scene=world_scene(estd, WORLD, 0))
    seen: list[tuple[np.ndarray, np.ndarray]] = []  # (the jar's pose, the opener's TCP) in the unscrew

    def watch(_: float) -> None:
        if run.executor.machine.innermost().visit.path == "unscrew_cap":
            seen.append((run.robot.object_pose().copy(), run.others["left"].true_tcp()[:3, 3].copy()))

    run.observers.append(watch)
    end: list[np.ndarray] = []  # the jar's pose as the task ended
    outcome = run.execute(afterwards=lambda sim: end.append(sim.object_pose().copy()))
    assert outcome.succeeded, outcome.summary
    assert [v.path for v in outcome.visits][:6] == ["turn_beside", "come_level", "near_jar", "grasp_jar", "to_vantage",
                                                   "above_cap"]
    assert seen
    for jar, opener in seen:
        assert jar[2, 3] > STANDING[2] + VANTAGE_RISE - 0.01, jar[:3, 3]  # held up, not dropped or pushed out
        assert jar[2, 2] > UPRIGHT, jar[:3, 2]
        top = jar[:3, 3] + jar[:3, 2] * 0.0525
        assert np.linalg.norm(opener[:2] - top[:2]) < 0.03  # its hand over the cap
    cap = run.caps["jar"]
    assert cap.free and cap.rests == "table", cap  # off its thread and on the table: the simulator agrees
    jar = end[0]
    assert abs(jar[2, 3] - STANDING[2]) < 0.005 and jar[2, 2] > UPRIGHT, jar  # the jar stands on the table again


def test_a_robot_with_one_arm_is_refused_at_the_openers_role(tmp_path: Path) -> None:
    result = CliRunner().invoke(main, ["run", str(TASK), "--robot", "melfa", "--world", str(WORLD)])
    assert result.exit_code == 4, result.output
    assert f"{TASK}:18:3: error[TRN005]: melfa: cannot give role 'opener' an arm" in result.output
    assert "Traceback" not in result.output
