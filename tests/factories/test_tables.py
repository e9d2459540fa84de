"""Every row of thesis Tables 7.3 (Tombatossals) and 7.4 (Melfa), our Baxter table, and every refusal."""

from __future__ import annotations

import numpy as np
import pytest

from atd.model.controllers import SensorKind

from atd.model import Environment, HandShape, Movement, Obstacle, State, StateType
from atd.model.task import ContainerInfo, Pose
from atd.model.vocabulary import PerceptionMethod
from atd.model.estd import describe
from factories.base import MappingContext, Unmappable
from factories.registry import create
from tests.translator.helpers import at, every_factory, one_state_task
from translator import translate

TARGET = at(0.10, 0.10, 0.025)


def _state(kind: StateType, **fields) -> State:
    path = TARGET if kind in (StateType.MOVE, StateType.PUSH, StateType.TRANSPORT, StateType.PLACE,
                              StateType.SLIDE) else ()
    return State(name="s", type=kind, **{"path": path, **fields})


def _map(robot: str, state: State, arm: str | None = None, environment=None):
    """What the translator gets for the state (`map_state`: a primitive the robot lacks refused first)."""
    task = one_state_task(state).model_copy(update={"environment": environment})
    return create(robot, arm).map_state(state, MappingContext(task))


# Table 7.3: abstract -> Tombatossals primitive, its controllers, and the extra parameter it carries
# (its slide is refused: tests/primitives/test_slide.py).
TABLE_7_3 = [
    (StateType.GRASP, "robust_grasp", "robust_grasp_approach", "robust_grasp_hand", ("hand", "pregrasp_size", 0.562)),
    (StateType.MOVE, "transport", "cartesian_move", "hold_position", ("arm", "force_threshold", 15.0)),
    (StateType.PUSH, "transport", "push", "hold_position", ("arm", "push_force", 0.35)),
    (StateType.TRANSPORT, "transport", "cartesian_move", "hold_position",
     ("arm", "obstacles", ((0.25, 0.22, 0.06),))),
    (StateType.PLACE, "place", "place", "hold_position", ("arm", "force_threshold", 5.0)),
    (StateType.RELEASE, "release", "release_retreat", "open_to", ("hand", "hand_position", 1.0)),
]


@pytest.mark.parametrize("kind, primitive, arm, hand, extra", TABLE_7_3, ids=[r[0].value for r in TABLE_7_3])
def test_table_7_3_tombatossals(kind, primitive, arm, hand, extra):
    env = Environment(obstacles=(Obstacle(position=(0.25, 0.22, 0.06)),))
    mapping = _map("tombatossals", _state(kind), environment=env)
    assert (mapping.primitive, mapping.arm.name, mapping.hand.name) == (primitive, arm, hand)
    role, name, value = extra
    assert getattr(mapping, role).params[name] == value


def test_table_7_3_grasp_uses_wrist_force_torque_and_tactile():
    mapping = _map("tombatossals", _state(StateType.GRASP, hand_shape=HandShape.PINCH_GRASP))
    assert mapping.arm.params["force_threshold"] == 2.0 and mapping.arm.params["torque_threshold"] == 5.0
    assert mapping.hand.params["preshape"] == "pinch_grasp_preshape"
    task = one_state_task(_state(StateType.GRASP))
    factory = create("tombatossals")
    stable = factory.map_event("grasp_stable", None, task.transitions[0], MappingContext(task))
    assert stable.sensors == ("tactile_f1", "tactile_f2", "tactile_f3") and stable.params["min_pads"] == 2


def _leaves(node):
    children = getattr(node, "children", None)
    return [node] if children is None else [leaf for child in children for leaf in _leaves(child)]


def test_a_transport_succeeds_only_after_holding_its_object_still_at_the_target():
    """The arm must have been done for 2 s, the object held all along (grasp_stable)."""
    task = one_state_task(_state(StateType.TRANSPORT))
    for robot in ("melfa", "tombatossals", "baxter"):
        success = create(robot).map_event("success", None, task.transitions[0], MappingContext(task))
        arm_done = [leaf for leaf in _leaves(success) if leaf.kind == "arm_done"]
        assert [leaf.params["for_time"] for leaf in arm_done] == [2.0], (robot, describe(success))


# Table 7.4: abstract -> Melfa primitive and controllers.
TABLE_7_4 = [
    (StateType.GRASP, "grasp", "jaw_grasp_correction", "close_until_force"),
    (StateType.MOVE, "move", "cartesian_move", "hold_position"),
    (StateType.PUSH, "move", "push", "hold_position"),
    (StateType.TRANSPORT, "transport", "cartesian_move", "squeeze"),
    (StateType.PLACE, "place", "place", "squeeze"),
    (StateType.RELEASE, "release", "hold", "open_to"),
]


@pytest.mark.parametrize("kind, primitive, arm, hand", TABLE_7_4, ids=[r[0].value for r in TABLE_7_4])
def test_table_7_4_melfa(kind, primitive, arm, hand):
    mapping = _map("melfa", _state(kind))
    assert (mapping.primitive, mapping.arm.name, mapping.hand.name) == (primitive, arm, hand)


def test_table_7_4_grasp_closes_until_the_tactile_grasp_force():
    hand = _map("melfa", _state(StateType.GRASP)).hand
    assert hand.params == {"grasp_force": 15.0, "closing_speed": 0.04, "force_source": "tactile", "max_recentre": 0.01}


def test_table_7_4_transport_keeps_squeezing_with_the_grasp_force():
    assert _map("melfa", _state(StateType.TRANSPORT)).hand.params["grasp_force"] == 15.0


def test_a_melfa_place_weighs_what_its_jaws_hold_and_squeezes_it_down():
    """Not Table 7.4's transport: the place primitive, which puts the object, not the TCP, on the target."""
    task = one_state_task(_state(StateType.PLACE))
    estd = translate(task, create("melfa")).estd
    assert estd.states[0].arm.params["weigh_time"] > 0.0 and estd.states[0].hand.params["grasp_force"] == 15.0
    assert describe(estd.transitions[0].events[0].condition) == "all(arm_done, hand_done)"


def test_table_7_4_release_opens_to_the_hand_position():
    assert _map("melfa", _state(StateType.RELEASE, hand_opening=0.4)).hand.params["hand_position"] == 0.4


def test_table_7_4_has_no_slide():
    with pytest.raises(Unmappable, match=r"the Melfa has no slide primitive \(thesis Table 7.4\)"):
        _map("melfa", _state(StateType.SLIDE))


def test_slide_refusal_reaches_the_user_with_file_line_and_robot(atd_file):
    from atd.model import load_task

    path = atd_file("""
        <statemachine>
          <state name="wipe" type="slide"><path><position>0.1 0.1 0.03</position></path></state>
          <state name="done" type="success"/>
          <transition origin="wipe" destination="done"><success/></transition>
        </statemachine>
    """)
    result = translate(load_task(path)[0], create("melfa"))
    assert result.estd is None
    assert result.diagnostics[0].render().startswith(
        f"{path}:2:3: error[TRN001]: melfa: cannot map slide state 'wipe': the Melfa has no slide primitive")


@pytest.mark.parametrize("field", ["hand_shape", "preshape"])
@pytest.mark.parametrize("shape", [HandShape.HOOK_GRASP, HandShape.HOOK_GRASP_PRESHAPE])
def test_sdh2_refuses_a_hook_grasp(field, shape):
    with pytest.raises(Unmappable, match="the Schunk SDH2 cannot make a hook grasp"):
        _map("tombatossals", _state(StateType.GRASP, **{field: shape}), arm="left")
    assert _map("tombatossals", _state(StateType.GRASP, **{field: shape}), arm="right").primitive == "robust_grasp"


def test_a_target_outside_the_workspace_is_refused_for_every_robot():
    for factory in every_factory():
        state = State(name="far", type=StateType.MOVE, path=at(0.10, 0.10, 1.50))
        with pytest.raises(Unmappable, match=r"target \(0.1, 0.1, 1.5\) is out of reach of the .* hand pointing down"):
            factory.map_node(state, MappingContext(one_state_task(state)))


def test_the_shared_work_area_is_reachable_by_every_robot_and_arm():
    """x in [0, 0.2], y in [-0.15, 0.15], z in [0.02, 0.25]: where the examples work (docs/atd-format.md)."""
    for factory in every_factory():
        for x in (0.0, 0.2):
            for y in (-0.15, 0.15):
                for z in (0.02, 0.25):
                    factory.check_reach((x, y, z))  # raises Unmappable when out of reach


@pytest.mark.parametrize("kind", [StateType.PUSH, StateType.SLIDE])
def test_push_or_slide_without_a_path_is_refused(kind):
    with pytest.raises(Unmappable, match=f"where to {kind.value} it"):
        _map("baxter" if kind is StateType.SLIDE else "tombatossals", State(name="s", type=kind))


def test_no_path_and_no_object_pose_is_refused():
    state = State(name="s", type=StateType.MOVE)
    with pytest.raises(Unmappable, match="no object pose to derive a target from"):
        create("baxter").map_node(state, MappingContext(one_state_task(state, obj=None)))


@pytest.mark.parametrize("kind, movement, target", [
    (StateType.MOVE, Movement.FREE, (0.10, -0.05, 0.15)),  # approach: above the object
    (StateType.MOVE, Movement.GUARDED, (0.10, -0.05, 0.025)),  # guarded descent: to grasp height
    (StateType.TRANSPORT, None, (0.10, -0.05, 0.125)),  # lift
    (StateType.PLACE, None, (0.10, -0.05, 0.025)),  # put back
])
def test_targets_are_derived_from_the_object_when_there_is_no_path(kind, movement, target):
    arm = _map("baxter", State(name="s", type=kind, movement=movement)).arm
    assert arm.params["target"] == pytest.approx(target)


def test_parallel_jaw_maps_other_shapes_to_the_closest_with_a_note():
    for robot in ("melfa", "baxter"):
        mapping = _map(robot, _state(StateType.MOVE, hand_shape=HandShape.POWER_GRASP_PRESHAPE))
        assert mapping.hand.params["shape"] == "open"
        assert "cannot make 'power_grasp_preshape'; using the closest shape 'open'" in mapping.notes[0]
        assert _map(robot, _state(StateType.MOVE, hand_shape=HandShape.CYLINDRICAL_GRASP)).hand.params["shape"] == \
            "pinch_grasp"


def test_sdh2_makes_a_cylinder_where_a_move_asks_for_a_hook():
    mapping = _map("tombatossals", _state(StateType.MOVE, hand_shape=HandShape.HOOK_GRASP_PRESHAPE), arm="left")
    assert mapping.hand.params["shape"] == "cylindrical_grasp_preshape" and mapping.notes


def test_baxter_reads_its_noisy_force_sensor_with_raised_filtered_thresholds():
    place = _map("baxter", _state(StateType.PLACE)).arm
    assert place.params["force_threshold"] == 10.0 and place.params["filter_time"] == 0.05
    down = _state(StateType.EXPLORE, direction=(0.0, 0.0, -1.0))
    explore = create("baxter").map_state(down, MappingContext(one_state_task(down))).arm
    assert explore.params["force_threshold"] == 8.0 and explore.params["filter_time"] == 0.05  # 3 N raw: noise
    assert create("melfa").map_state(down, MappingContext(one_state_task(down))).arm.params["force_threshold"] == 3.0
    task = one_state_task(_state(StateType.GRASP))
    factory = create("baxter")
    ctx = MappingContext(task)
    assert describe(factory.map_event("grasp_stable", None, task.transitions[0], ctx)) == \
        "all(gripper_force_above, gripper_opening_above)"
    assert describe(factory.map_event("grasp_lost", None, task.transitions[0], ctx)) == "gripper_opening_below"
    collision = factory.map_event("collision", None, task.transitions[0], ctx)
    assert collision.params["force_threshold"] == 30.0 and collision.params["filter_time"] == 0.05


def test_hardware_failure_is_arm_or_hand_failure_on_every_robot():
    task = one_state_task(_state(StateType.MOVE))
    for factory in every_factory():
        node = factory.map_event("hardware_failure", None, task.transitions[0], MappingContext(task))
        assert describe(node) == "any(arm_fault, hand_fault, simulation_unstable)"


# The perceptual primitives' states need what they act on: a container, a method, a direction.
PERCEIVING = {StateType.PERCEIVE: {"container": "box", "method": PerceptionMethod.VISION},
              StateType.EXPLORE: {"direction": (0.0, 0.0, -1.0)}}
BOX_KNOWN = Environment(containers=(ContainerInfo(name="box", pose=Pose.from_position((0.1, -0.08, 0.0)),
                                                  size=(0.3, 0.25, 0.1)),))


def test_each_mapping_table_row_says_what_the_factory_does():
    for factory in every_factory():
        for row in factory.node_table:
            state = _state(StateType(row.abstract), **PERCEIVING.get(StateType(row.abstract), {}))
            context = MappingContext(one_state_task(state).model_copy(update={"environment": BOX_KNOWN}))
            if row.concrete == "-":
                with pytest.raises(Unmappable):
                    factory.map_state(state, context)
            else:
                assert factory.map_state(state, context).primitive == row.concrete
        assert {StateType(r.abstract) for r in factory.node_table if r.concrete != "-"} == factory.primitives


def test_reach_is_judged_on_the_simulated_robot_itself():
    """A point the arm can just reach is accepted, one a little beyond its stretched arm is not,
    and the answer comes from the same description the simulator builds."""
    from factories.reach import Reach
    factory = create("melfa")
    reach = Reach(factory.robot)
    assert reach.reachable((0.1, 0.0, 0.1))
    far = reach.shoulder + (reach.stretched + 0.01) * np.array([1.0, 0.0, 0.0])
    assert not reach.reachable(tuple(far))


def test_every_tactile_sensor_a_factory_names_is_a_pad_of_the_simulated_hand():
    from primitives.conditions import pad_indices
    from atd.sim.simrobot import robot_info
    for factory in every_factory():
        names = factory.arm.sensors_of(SensorKind.TACTILE)
        hand = robot_info(factory.robot).hand
        assert len(set(pad_indices(hand, names))) == len(names), (factory.name, factory.arm.name)


def test_every_factory_can_be_told_to_use_the_naive_grasp():
    """Thesis 3.4.1's baseline: grasp states become the naive grasp, everything else is unchanged."""
    state = State(name="g", type=StateType.GRASP, hand_shape=HandShape.PINCH_GRASP)
    move = State(name="m", type=StateType.MOVE, path=at(0.1, 0.0, 0.1))
    for robot, arm in (("melfa", None), ("baxter", "right"), ("tombatossals", "right"), ("tombatossals", "left")):
        naive, robust = create(robot, arm, grasp="naive"), create(robot, arm)
        mapping = naive.map_state(state, MappingContext(one_state_task(state)))
        assert (mapping.arm.name, mapping.hand.name) == ("naive_grasp_approach", "naive_grasp_hand")
        context = MappingContext(one_state_task(move))
        assert naive.map_state(move, context) == robust.map_state(move, context)
    with pytest.raises(ValueError, match="grasp must be one of: robust, naive"):
        create("melfa", grasp="clumsy")


@pytest.mark.parametrize("factory", every_factory(), ids=lambda f: f"{f.name}-{f.arm.name}")
def test_every_shape_a_hand_claims_to_make_is_a_posture_of_its_robot(factory) -> None:
    """A shape the factory passes on unchanged must exist in the robot's description: a
    grasp with 'extend_finger' on either Tombatossals hand was a KeyError in the reach check."""
    missing = sorted(s.value for s in factory.arm.hand.shapes if s.value not in factory.robot.hand.postures)
    assert not missing, missing
    for shape in HandShape:
        assert factory.shape(shape)[0].value in factory.robot.hand.postures, shape
