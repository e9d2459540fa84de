"""Perturbations change the truth, never the belief: each model's draw and where it lands."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from atd.campaign.perturbation import (ApproachError, HandPhysics, NoPerturbation, ObjectPhysics, ObjectPose,
                                      PerturbationModel, SensorError, Truth, approach_states, approach_taken)
from atd.model import load_task
from atd.runtime.session import belief_scene
from factories.registry import create
from tests.conftest import REPO
from translator import translate

TASK = REPO / "examples" / "grasp_and_lift.xml"


@pytest.fixture(scope="module")
def belief():
    task, _ = load_task(TASK)
    return translate(task, create("melfa")).estd


def _draws(model: PerturbationModel, n: int = 200) -> list[dict[str, float]]:
    rng = np.random.default_rng(3)
    return [model.draw(rng) for _ in range(n)]


def test_the_approach_error_is_drawn_within_its_magnitudes_in_both_directions() -> None:
    draws = _draws(ApproachError(model="approach", translation=0.05, rotation=15))
    for axis in ("dx", "dy", "dz"):
        values = [d[axis] for d in draws]
        assert max(abs(v) for v in values) <= 0.05 and min(values) < -0.03 and max(values) > 0.03
    for axis in ("roll", "pitch", "yaw"):
        values = [d[axis] for d in draws]
        assert max(abs(v) for v in values) <= 15 and min(values) < -10 and max(values) > 10
    d = draws[0]
    assert d["translation"] == pytest.approx(math.dist((0, 0, 0), (d["dx"], d["dy"], d["dz"])))
    assert 0 < d["rotation"] <= math.sqrt(3) * 15


def test_the_approach_error_moves_only_the_moves_that_bring_the_hand_to_the_grasp(belief) -> None:
    assert approach_states(belief) == {"approach", "preshape_hand"}
    values = {"dx": 0.01, "dy": -0.02, "dz": 0.03, "roll": 0.0, "pitch": 0.0, "yaw": 0.0}
    taken = approach_taken(belief, values)
    before = {s.name: s for s in belief.states}
    for state in taken.states:
        if state.name in ("approach", "preshape_hand"):
            moved = np.subtract(state.arm.params["target"], before[state.name].arm.params["target"])
            assert moved == pytest.approx([0.01, -0.02, 0.03])
        else:
            assert state == before[state.name], f"{state.name} must be left as the robot planned it"
    assert taken.object == belief.object, "the robot's belief about the object is unchanged"


def test_a_turned_approach_swings_about_the_believed_object_centre_and_tilts_the_hand(belief) -> None:
    values = {"dx": 0.0, "dy": 0.0, "dz": 0.0, "roll": 0.0, "pitch": 10.0, "yaw": 0.0}
    taken = {s.name: s for s in approach_taken(belief, values).states}
    planned = {s.name: s for s in belief.states}
    centre = np.array(belief.object.pose.as_array()[:3, 3])
    for name in ("approach", "preshape_hand"):
        new, old = (np.array(x[name].arm.params["target"]) for x in (taken, planned))
        assert np.linalg.norm(new - centre) == pytest.approx(np.linalg.norm(old - centre))
        assert taken[name].arm.params["tilt"] == (0.0, 10.0, 0.0)
    high = np.array(taken["approach"].arm.params["target"]) - centre
    assert high[0] == pytest.approx(math.sin(math.radians(10)) * np.linalg.norm(high))


def test_object_pose_and_physics_change_the_true_world_only(belief) -> None:
    scene = belief_scene(belief)
    truth = Truth(belief, scene, create("melfa").robot)
    moved = ObjectPose(model="object_pose").apply(truth, {"dx": 0.02, "dy": -0.01, "yaw": 90.0})
    assert moved.scene.object.pose[:3, 3] == pytest.approx(scene.object.pose[:3, 3] + [0.02, -0.01, 0.0])
    assert moved.scene.object.pose[:3, 0] == pytest.approx([0.0, 1.0, 0.0])
    heavy = ObjectPhysics(model="object_physics").apply(truth, {"mass_scale": 2.0, "friction_scale": 0.5}).scene
    assert heavy.object.mass == pytest.approx(2 * scene.object.mass)
    assert heavy.object.friction == pytest.approx(0.5 * scene.object.friction)
    assert scene.object.mass == belief.object.weight, "the belief is untouched"
    assert moved.estd is belief and moved.robot is truth.robot


def test_the_sensor_perturbation_scales_noise_and_bias_and_leaves_ideal_sensors_ideal() -> None:
    robot = create("baxter").robot
    truth = Truth(None, None, robot)  # type: ignore[arg-type]
    noisy = SensorError(model="sensors").apply(truth, {"noise_scale": 3.0, "bias_scale": 2.0}).robot
    wrench, scaled = robot.sensors["wrench"], noisy.sensors["wrench"]
    assert np.asarray(scaled.noise_std) == pytest.approx(3 * np.asarray(wrench.noise_std))
    assert np.asarray(scaled.bias) == pytest.approx(2 * np.asarray(wrench.bias))
    assert np.any(np.asarray(wrench.noise_std) > 0), "Baxter's virtual wrist sensor is noisy"
    assert NoPerturbation(model="none").apply(truth, {}) is truth


def test_a_trial_draws_the_same_values_from_the_same_seed() -> None:
    model = ObjectPhysics(model="object_physics")
    first = model.draw(np.random.default_rng([42, 1]))
    assert model.draw(np.random.default_rng([42, 1])) == first
    assert 0.5 <= first["mass_scale"] <= 2.0 and 0.5 <= first["friction_scale"] <= 1.5


def test_the_perturbed_tasks_are_the_ones_in_the_spec(tmp_path: Path) -> None:
    from atd.campaign.cells import plans
    from atd.campaign.spec import load_spec

    spec = tmp_path / "s.toml"
    spec.write_text(f'name = "s"\ntasks = ["{TASK}"]\nrobots = ["melfa", "baxter"]\ngrasps = ["naive", "robust"]\n'
                    'trials = 3\n[perturbations.shift]\nmodel = "object_pose"\n')
    loaded, found = load_spec(spec)
    assert loaded is not None, found
    chosen = plans(loaded)
    assert len(chosen) == 2 * 2 * 3
    assert len({p.seed for p in chosen}) == len(chosen), "every trial has its own seed"
    assert {p.cell.perturbation for p in chosen} == {"shift"}


@pytest.mark.parametrize("scales", ["[0.0, 0.0]", "[nan, 2.0]", "[1.0, inf]", "[2.0, 1.0]", "[1e-300, 1.0]"])
def test_a_mass_scale_no_engine_can_simulate_is_refused_in_the_spec(tmp_path: Path, scales: str) -> None:
    """A mass scaled to 0 made every trial a MuJoCo error; NaN and infinities slipped through too."""
    from atd.campaign.spec import load_spec

    spec = tmp_path / "s.toml"
    spec.write_text(f'name = "s"\ntasks = ["{TASK}"]\nrobots = ["melfa"]\n'
                    f'[perturbations.heavy]\nmodel = "object_physics"\nmass = {scales}\n')
    loaded, found = load_spec(spec)
    assert loaded is None and [d.code for d in found] == ["CMP012"]
    assert "[0.01, 100]" in found[0].message


@pytest.mark.parametrize("line", ["budget = true", "trials = true", "base_seed = false", "trials = 2.0",
                                  "[perturbations.heavy]\nmodel = \"object_physics\"\nmass = [true, 2]"])
def test_a_flag_where_a_spec_number_belongs_is_not_taken_for_one(tmp_path: Path, line: str) -> None:
    """pydantic read `budget = true` as a budget of 1 s and ran the campaign."""
    from atd.campaign.spec import load_spec

    spec = tmp_path / "s.toml"
    spec.write_text(f'name = "s"\ntasks = ["{TASK}"]\nrobots = ["melfa"]\n{line}\n')
    loaded, found = load_spec(spec)
    assert loaded is None and [(d.code, d.loc.line) for d in found] == [("CMP012", line.count("\n") + 4)]
    assert "should be a valid" in found[0].message


def test_a_heavier_hand_changes_the_simulated_robot_only() -> None:
    """The hand model scales every hand link's mass (and explicit inertia) and the finger
    servos' gains; the arm and the factory's description are left as they are."""
    factory = create("tombatossals", "right")
    believed = factory.robot
    truth = HandPhysics(model="hand_physics").apply(Truth(None, None, believed),  # type: ignore[arg-type]
                                                   {"hand_mass_scale": 1.5, "servo_scale": 0.5}).robot
    assert truth.hand_mass == pytest.approx(1.5 * believed.hand_mass)
    hand = set(believed.hand_links)
    for old, new in zip(believed.links, truth.links):
        if old.name not in hand:
            assert new == old, f"{old.name} is not part of the hand"
        elif old.joint is not None:
            assert (new.joint.servo.kp, new.joint.servo.kv) == pytest.approx((old.joint.servo.kp / 2, old.joint.servo.kv / 2))
    assert factory.robot.hand_mass == pytest.approx(believed.hand_mass) and factory.info.hand.mass == pytest.approx(
        believed.hand_mass), "the belief is untouched"


def _spec_errors(tmp_path: Path, table: str) -> tuple[Path, list]:
    from atd.campaign.spec import load_spec

    spec = tmp_path / "s.toml"
    spec.write_text(f'name = "s"\ntasks = ["{TASK}"]\nrobots = ["melfa"]\n\n[perturbations.shift]\n{table}\n')
    loaded, found = load_spec(spec)
    assert loaded is None
    return spec, found


def test_a_parameter_another_model_has_is_a_located_spec_error(tmp_path: Path) -> None:
    """`x` belongs to object_pose: on an approach error it was silently ignored."""
    from click.testing import CliRunner

    from atd.cli import main

    spec, found = _spec_errors(tmp_path, 'model = "approach"\nrotation = 5\nx = 0.02')
    assert [(d.code, d.loc.file, d.loc.line) for d in found] == [("CMP010", str(spec), 8)]
    assert found[0].message == "unknown key 'perturbations.shift.x': perturbation model 'approach' has no parameter 'x'"
    assert found[0].hint == "the 'approach' model's parameters: translation, rotation ('x' belongs to 'object_pose')"
    result = CliRunner().invoke(main, ["campaign", "run", str(spec), "--store", str(tmp_path / "s.sqlite")])
    assert result.exit_code == 1 and f"{spec}:8:1: error[CMP010]" in result.stderr
    assert not (tmp_path / "s.sqlite").exists()


@pytest.mark.parametrize(("table", "expected"), [
    ('model = "object_physics"\nnoise = [1.0, 2.0]',
     ("CMP010", 7, "the 'object_physics' model's parameters: mass, friction ('noise' belongs to 'sensors')")),
    ('model = "none"\ntranslation = 0.01', ("CMP010", 7, "the 'none' model's parameters: none ('translation' belongs to 'approach')")),
    ('model = "hand_physics"\nmass = [0.0, 2.0]', ("CMP012", 7, None)),
    ('model = "aproach"', ("CMP012", 6, "did you mean 'approach'?")),
    ('translation = 0.01', ("CMP011", 5, "add model = ..., one of none, approach, object_pose, object_physics, sensors, "
                                         "hand_physics, cap_approach")),
])
def test_a_perturbation_table_is_checked_against_its_own_model(tmp_path: Path, table: str, expected: tuple) -> None:
    _, found = _spec_errors(tmp_path, table)
    assert [(d.code, d.loc.line, d.hint) for d in found] == [expected]
