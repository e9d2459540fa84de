"""Issue 10, zero false successes: trials of the Table 3.3 preset that once ended in
`succeeded` while the object, squeezed out between the jaws, crept and turned in the hand
during the judge's 2 s hold (the jaws kept closing at 3-4 mm/s under a steady grip force),
or, caged below the Baxter's paddles, dropped out of the hand and off the table.
`grasp_stable` after a transport now also needs the fingers to have stopped closing, so
each of these trials says success only when the judge, reading the simulator's ground
truth, agrees."""

from __future__ import annotations

import pytest

from atd.campaign.record import TrialRecord
from tests.primitives.conftest import preset_trials


def preset_trial(index: int, **cell: str) -> TrialRecord:
    """Trial `index` of the robust grasp with the approach error, in the cell `cell` names."""
    [record] = preset_trials((index,), grasp="robust", perturbation="approach", **cell)
    assert record.status == "ok", record.error
    return record


@pytest.mark.parametrize(("robot", "obj", "index"), [("melfa", "duck", 5), ("melfa", "duck", 7),
                                                       ("baxter", "duck", 5), ("baxter", "tape", 0),
                                                       ("baxter", "ball", 8), ("baxter", "duck", 6)])
def test_a_grip_that_keeps_closing_does_not_claim_the_object_held(robot: str, obj: str, index: int) -> None:
    """Since MuJoCo's friction is stiff against the normal force (impratio 100), the
    Baxter's duck trial 5 errs the other way: its lift ends on `grasp_lost` with the duck
    held (a false failure, as 39 of the Baxter's were in the preset before)."""
    record = preset_trial(index, robot=robot, engine="mujoco", object=obj)
    assert record.judged_succeeded or not record.task_succeeded, (
        f"the task said {record.summary!r}; the judge: {record.judge_reason}")


@pytest.mark.parametrize(("obj", "index"), [("mug", 6), ("duck", 8)])
def test_an_object_the_sdh2_holds_in_pybullet_stays_put_once_the_arm_stops(obj: str, index: int) -> None:
    """Preset trials whose two-finger grip, off centre after the approach error, let the
    object turn 29 and 11 degrees in the judge's hold while the task said success: the
    PyBullet finger servo's force limit, set once per control tick, lagged the finger."""
    record = preset_trial(index, robot="tombatossals", arm="left", engine="pybullet", object=obj)
    assert record.task_succeeded, record.summary
    assert record.judged_succeeded, record.judge_reason
    assert record.measurements["turn"] < 5.0 and record.measurements["slip"] < 0.01


def test_an_object_the_melfa_holds_while_its_grip_creeps_slowly_is_reported_held() -> None:
    """MuJoCo's PG70 grip on the steel weight creeps 0.8 mm/s: the judge sees it held still
    (1.5 mm in 2 s), and the lift must end in success, not time out waiting for stillness."""
    record = preset_trial(1, robot="melfa", engine="mujoco", object="weight")
    assert record.judged_succeeded and record.task_succeeded, (record.summary, record.judge_reason)


def test_a_lift_whose_pads_no_longer_press_enough_to_carry_the_weight_does_not_claim_it_held() -> None:
    """The Barrett lifted the 340 g steel weight (friction 0.5) with its pads' force falling
    to 3.2 N, under the 3.3 N friction needs to carry it, and said success; in the judge's
    hold it turned 16 degrees and slid out (PyBullet)."""
    record = preset_trial(4, robot="tombatossals", arm="right", engine="pybullet", object="weight")
    assert record.task_succeeded == record.judged_succeeded, (record.summary, record.judge_reason)


@pytest.mark.parametrize(("obj", "index"), [("wood", 0), ("duck", 5)])
def test_an_object_the_barrett_holds_in_mujoco_does_not_creep_round_in_its_pads(obj: str, index: int) -> None:
    """Held well within friction (the wood block at 4 N a pad), the object turned 5.2 and
    6.5 degrees in the judge's hold while the task said success: MuJoCo's soft friction let
    it creep, until friction was made stiff against the normal force (impratio 100)."""
    record = preset_trial(index, robot="tombatossals", arm="right", engine="mujoco", object=obj)
    assert record.task_succeeded == record.judged_succeeded, (record.summary, record.judge_reason)
    assert record.measurements.get("turn", 0.0) < 2.0, record.judge_reason


@pytest.mark.parametrize(("engine", "index"), [("pybullet", 9)])
def test_the_baxters_jaws_move_as_one_so_a_held_object_is_not_reported_lost(engine: str, index: int) -> None:
    """The Baxter's jaws are on one motor. Simulated as two jaws pushed alike, jaws and
    cylinder slid together towards one side during the lift; the jaw the opening is read
    from reached its closed stop, and the lift ended on `grasp_lost` with the cylinder held."""
    record = preset_trial(index, robot="baxter", engine=engine, object="cylinder")
    assert record.task_succeeded and record.judged_succeeded, (record.summary, record.judge_reason)


def test_a_lift_weighs_the_object_against_the_hand_in_free_air() -> None:
    """The empty hand's load is taken as the grasp's search begins a descent, risen clear of
    everything. Taken as the grasp began, it held the approach's push on the cylinder's top
    (4.3 N up), and the lifted cylinder read as no load: the lift timed out with it held."""
    record = preset_trial(5, robot="melfa", engine="mujoco", object="cylinder")
    assert record.task_succeeded and record.judged_succeeded, (record.summary, record.judge_reason)


def test_jaws_that_press_the_object_into_the_table_rise_off_it_before_the_lift() -> None:
    """Closing below the duck's widest point, the Melfa's jaws pressed it and the hand into
    the table (96 N up on the wrist); the lift, tared on that, read the push going as a
    collision and stopped at once. The arm now rises while the jaws close until the push
    is off."""
    record = preset_trial(2, robot="melfa", engine="pybullet", object="duck")
    assert record.task_succeeded and record.judged_succeeded, (record.summary, record.judge_reason)

