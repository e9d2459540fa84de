"""The three-finger robust grasp on trials of the Table 3.3 preset where it failed without
any added error (issue 10): the Barrett in PyBullet let a ball and the rubber duck slip
past its fingertips (the fingers closed on past a firm pinch), and the 340 g steel weight,
pinched at the configured 5 N, slid out of the hand within 2 s of a lift the task called a
success; in MuJoCo a pinched cylinder turned over 5 degrees in the Barrett's hand while it
was held, the two force-driven fingers drifting together. Each trial is judged by the
simulator, as a campaign judges it."""

from __future__ import annotations

import pytest

from atd.model import load_task
from factories.registry import create
from tests.primitives.conftest import EXAMPLES, lifted_but_at_most_one, preset_trials
from translator import translate

BARRETT = {"robot": "tombatossals", "arm": "right", "grasp": "robust", "perturbation": "none"}


@pytest.mark.parametrize("obj", ["ball", "duck"])
def test_the_barrett_holds_a_round_object_it_has_pinched(obj: str) -> None:
    [record] = preset_trials((0,), **BARRETT, engine="pybullet", object=obj)
    assert record.judged_succeeded and record.task_succeeded, (record.judge_reason, record.summary)


def test_the_barrett_squeezes_the_steel_weight_hard_enough_to_keep_it() -> None:
    """Trials 3 and 4 of the preset's cell were its false successes."""
    for record in preset_trials((3, 4), **BARRETT, engine="pybullet", object="weight"):
        assert record.judged_succeeded and record.task_succeeded, (record.judge_reason, record.summary)


def test_the_barretts_self_locking_fingers_keep_a_pinched_cylinder_still_in_mujoco() -> None:
    """Trials 0 and 3 turned 5.3 degrees in the judge's 2 s hold when the fingers held a
    constant effort, free to drift together."""
    for record in preset_trials((0, 3), **BARRETT, engine="mujoco", object="cylinder"):
        assert record.judged_succeeded and record.measurements["turn"] < 2.0, (record.judge_reason, record.summary)


def test_the_grasp_force_grows_with_the_weight_friction_must_carry() -> None:
    task, _ = load_task(EXAMPLES / "grasp_and_lift.xml")
    factory = create("tombatossals", arm="right")

    def grasp_force(weight: float, friction: float) -> float:
        obj = task.object.model_copy(update={"weight": weight, "friction": friction})
        estd = translate(task.model_copy(update={"object": obj}), factory).estd
        [state] = [s for s in estd.states if s.name == "grasp_object"]
        return float(state.hand.params["grasp_force"])

    assert grasp_force(0.15, 0.8) == 5.0  # the configured force carries it twice over
    assert grasp_force(0.34, 0.5) == pytest.approx(2 * 0.34 * 9.81 / (2 * 0.5), abs=1e-3)


def test_an_object_friction_cannot_carry_is_refused_not_squeezed_past_every_limit(tmp_path) -> None:
    """Found by the translation property test: 2 kg at friction 0.016 asked for 1,256 N per pad,
    an ESTD the translator's own check then refused as the factory's defect."""
    from click.testing import CliRunner

    from atd.cli import main

    text = (EXAMPLES / "grasp_and_lift.xml").read_text()
    slippery = tmp_path / "slippery.xml"
    slippery.write_text(text.replace("<weight>0.15</weight>", "<weight>2</weight>")
                        .replace("<friction>0.8</friction>", "<friction>0.015625</friction>"))
    result = CliRunner().invoke(main, ["translate", str(slippery), "--robot", "tombatossals", "--arm", "right", "-q"])
    assert result.exit_code == 4, result.output
    assert "only if each pad presses 1256 N" in result.output and "check the object's <weight> and <friction>" in result.output


def test_two_pinching_fingers_share_one_squeeze_and_do_not_walk_the_object_away() -> None:
    """The SDH2 in MuJoCo with the preset's approach error: pinched with one pad reading 3 N
    and the other 6 N (its contact partly off the pad), each finger's own force loop closed
    the weaker one on and on while the other gave way, and the pair carried the object 8 cm
    along the pinch line until the hold timed out (at 9c68463). A squeeze set by the weaker
    pad held speaker 3 at 2 and 7 N, its weaker pad still short of 4.5 N when the hold's 4 s
    ran out (at be8de63): the squeeze is the pads' mean."""
    lifted_but_at_most_one([("wood", 8), ("speaker", 2), ("duck", 1), ("speaker", 3)], robot="tombatossals",
                           arm="left", grasp="robust", perturbation="approach", engine="mujoco")
