"""A grasp needs room for the hand: the factory checks the hand's links, in the postures it
grasps with, against the obstacles around the object, including those of the task a
sub-task runs in (empty_the_box.xml's walls around pick_one.xml's grasp)."""

from __future__ import annotations

from atd.model import Environment, Obstacle, Pose, State, StateType, load_task
from factories.registry import create
from tests.conftest import KNOWN_BOX
from tests.translator.helpers import BOX, one_state_task
from translator import translate

# The walls of empty_the_box.xml, 150 mm apart inside; the Barrett's pinch knuckles stand
# 75 mm either side of its TCP, so its fingers would close on the walls.
X_WALLS = ((0.02, -0.08, 0.03), (0.18, -0.08, 0.03))


def _grasp_in(walls: tuple[tuple[float, float, float], ...], robot: str, arm: str):
    task = one_state_task(State(name="grasp", type=StateType.GRASP, hand_shape="pinch_grasp"),
                          obj=BOX.model_copy(update={"pose": Pose.from_position((0.10, -0.08, 0.025))}))
    task = task.model_copy(update={"environment": Environment(
        obstacles=tuple(Obstacle(position=w, size=(0.01, 0.16, 0.06)) for w in walls))})
    return translate(task, create(robot, arm))


def test_the_barrett_pinch_is_refused_between_walls_its_knuckles_stand_in():
    result = _grasp_in(X_WALLS, "tombatossals", "right")
    assert result.estd is None and [d.code for d in result.diagnostics] == ["TRN001"]
    message = result.diagnostics[0].message
    assert "Barrett BH8-280 in its 'pinch_grasp' posture" in message
    assert "(0.02, -0.08, 0.03)" in message and "(0.18, -0.08, 0.03)" in message
    assert "move the obstacle away" in result.diagnostics[0].hint


def test_the_same_pinch_maps_with_the_walls_moved_out_of_the_hand():
    # The preshape's fingertips stand 134 mm out, a wall's top must stay 1 cm clear of them.
    result = _grasp_in(((-0.06, -0.08, 0.03), (0.26, -0.08, 0.03)), "tombatossals", "right")
    assert result.estd is not None and result.diagnostics == []


def test_the_grippers_grasp_between_the_same_walls():
    for robot, arm in (("melfa", "main"), ("baxter", "right")):
        result = _grasp_in(X_WALLS, robot, arm)
        assert result.estd is not None, (robot, result.diagnostics)


def test_a_hand_must_keep_a_centimetre_from_the_walls():
    """The SDH2's thumb clears these walls by 4 mm on paper, and landed on one in both engines:
    the factory asks for HAND_CLEARANCE of room; with the walls 5 cm further out it maps."""
    refused = _grasp_in(X_WALLS, "tombatossals", "left")
    assert refused.estd is None and "SDH2" in refused.diagnostics[0].message
    assert _grasp_in(((-0.03, -0.08, 0.03), (0.23, -0.08, 0.03)), "tombatossals", "left").estd is not None


def test_a_sub_task_is_mapped_in_the_world_of_the_task_around_it():
    task, _ = load_task(KNOWN_BOX / "empty_the_box.xml")
    refused = translate(task, create("tombatossals", "right"))
    assert refused.estd is None
    assert [d.loc.file.rsplit("/", 1)[-1] for d in refused.diagnostics] == ["pick_one.xml"]
    estd = translate(task, create("baxter")).estd
    lift = next(s for s in next(s for s in estd.states if s.name == "pick_one").machine.states if s.name == "lift_out")
    assert len(lift.arm.params["obstacles"]) == len(task.environment.obstacles)
    alone, _ = load_task(KNOWN_BOX / "pick_one.xml")  # the round on its own has no walls around it
    assert translate(alone, create("tombatossals", "right")).estd is not None
