"""Issue 31 in translation: a state acts on the object it names, the ESTD carries the task's
objects, containers, values and sub-task inputs for the runtime, a sub-task's outcome becomes
a condition on how its machine ended, and perception no robot maps yet is refused with why."""

from __future__ import annotations

import shutil

import numpy as np
import pytest

from lxml import etree

from atd.model import Event, EventType, ObjectInfo, Pose, State, StateType, Task, Transition, load_task
from atd.model.estd import Estd, EstdState, leaves
from atd.model.estd_xml import estd_to_json, estd_to_xml, parse_estd, parse_estd_json
from atd.model.task import ContainerInfo, Environment, Value
from atd.model.vocabulary import ValueKind
from factories.registry import create
from schemas import schema_path
from tests.conftest import EXAMPLES, KNOWN_BOX, REPO
from tests.translator.helpers import every_factory
from translator import translate

THESIS = REPO / "tests" / "data" / "empty_the_box"
MUG = ObjectInfo(name="mug", pose=Pose.from_position((0.10, 0.05, 0.025)))
DUCK = ObjectInfo(name="duck", pose=Pose.from_position((0.12, -0.06, 0.025)))
BOX = ContainerInfo(name="box", pose=Pose.from_position((0.10, -0.08, 0.0)), size=(0.3, 0.25, 0.1))


def _two_objects(state: State) -> Task:
    return Task(known_objects=(MUG, DUCK), environment=Environment(containers=(BOX,)),
                states=(state, State(name="done", type=StateType.SUCCESS)),
                transitions=(Transition(origin=state.name, destination="done", events=(Event(type=EventType.SUCCESS),)),))


def test_a_state_is_mapped_for_the_object_it_names():
    """A move to the duck, with no path, ends above the duck, not above the task's first object."""
    for name, obj in (("duck", DUCK), ("mug", MUG)):
        task = _two_objects(State(name="go", type=StateType.MOVE, object=name))
        state = translate(task, create("melfa")).estd.states_by_name["go"]
        x, y, _ = state.arm.params["target"]
        assert (round(x, 3), round(y, 3)) == obj.pose.position[:2] and state.object == name


def test_the_estd_carries_objects_containers_and_the_state_s_object():
    task = _two_objects(State(name="go", type=StateType.GRASP, object="duck"))
    for factory in every_factory():
        estd = translate(task, factory).estd
        assert list(estd.objects) == ["mug", "duck"] and estd.environment.containers == (BOX,)
        assert estd.states_by_name["go"].object == "duck"
        assert parse_estd(estd_to_xml(estd), "x.xml") == (estd, [])
        assert parse_estd_json(estd_to_json(estd), "x.json") == (estd, [])


def test_values_and_inputs_read_back_from_both_estd_forms_and_satisfy_the_xsd():
    """What the runtime will use: which values a state writes and reads, and what a sub-task is given."""
    inner = Estd(robot="melfa", arm="main", initial="reach", inputs=(Value(name="approach", kind=ValueKind.POSE),),
                 states=(EstdState(name="reach", type=StateType.SUCCESS, atd="reach", target_from="approach"),))
    estd = Estd(robot="melfa", arm="main", initial="look", environment=Environment(containers=(BOX,)), states=(
        EstdState(name="look", type=StateType.SUCCESS, atd="look",
                  writes=(Value(name="approach", kind=ValueKind.POSE), Value(name="seen", kind=ValueKind.COUNT))),
        EstdState(name="take", type=StateType.TASK, atd="take", machine=inner, inputs={"approach": "approach"})))
    data = estd_to_xml(estd)
    schema = etree.XMLSchema(etree.parse(str(schema_path("estd.xsd"))))
    assert schema.validate(etree.fromstring(data)), schema.error_log
    assert parse_estd(data, "x.xml") == (estd, [])
    assert parse_estd_json(estd_to_json(estd), "x.json") == (estd, [])
    assert b'<writes name="seen" kind="count"/>' in data and b'<target from="approach"/>' in data
    assert b'<input name="approach" from="approach"/>' in data and b'<input name="approach" kind="pose"/>' in data


def test_a_sub_task_outcome_becomes_a_condition_on_the_end_state_it_names(tmp_path):
    shutil.copy(KNOWN_BOX / "pick_one.xml", tmp_path)
    text = (KNOWN_BOX / "empty_the_box.xml").read_text()
    (tmp_path / "empty.xml").write_text(text.replace("<error/>", '<outcome name="nothing_there"/>'))
    task, found = load_task(tmp_path / "empty.xml")
    assert found == []
    estd = translate(task, create("melfa")).estd
    edge = next(t for t in estd.transitions if t.atd == "pick_one->box_empty")
    assert edge.events[0].type is EventType.OUTCOME
    assert (edge.events[0].condition.kind, edge.events[0].condition.params) == \
        ("subtask_ended_in", {"end_state": "nothing_there"})
    assert parse_estd(estd_to_xml(estd), "x.xml") == (estd, [])


def test_every_robot_maps_perception_with_its_own_hand_and_reads_targets_at_run_time():
    task, found = load_task(THESIS / "empty_the_box.xml")
    assert found == []
    for factory in every_factory():
        estd = translate(task, factory).estd
        assert estd is not None, factory.name
        look = estd.states_by_name["look"]
        assert look.arm.name == "perceive" and look.arm.params["method"] == "vision"
        assert look.arm.params["hand_radius"] == round(factory.robot.hand_radius("closed"), 6)
        assert look.arm.params["grasp_extent"] == tuple(round(e, 6) for e in factory.robot.hand_extent("open"))
        # the part of the closed hand a sweep meets objects with: its tip, never wider than the hand
        tip = look.arm.params["sweep_extent"]
        assert tip == tuple(round(e, 6) for e in factory.robot.hand_extent("closed", 0.02))
        assert all(t <= e for t, e in zip(tip, factory.robot.hand_extent("closed")))
        # the approach keeps the hand clear of the rim whatever the grasp opens it to (an SDH2
        # perceives closed, its fingertips 9 cm short of its TCP)
        assert look.arm.params["grasp_reach"] >= max(map(factory.robot.hand_reach, factory.robot.hand.postures)) - 1e-6
        assert look.arm.params["container_size"] == (0.30, 0.25, 0.10)
        found_it = next(t for t in estd.transitions if t.atd == "look->take_one_out").events[0].condition
        assert (found_it.kind, found_it.params) == ("object_found", {"value": "approach"})
        inner = estd.states_by_name["take_one_out"].machine
        reach = inner.states_by_name["reach"]
        assert reach.target_from == "approach" and "target" not in reach.arm.params
        feel = inner.states_by_name["feel"]
        assert feel.arm.name == "explore" and feel.arm.params["writes"] == "touched"
        contact = next(t for t in inner.transitions if t.atd == "feel->grasp").events[0].condition
        assert contact.kind == "arm_done"


def test_blind_exploration_sweeps_with_the_narrower_of_the_closed_and_stretched_hand():
    """The SDH2's fist sticks its thumb 11.5 cm out, its stretched fingers 5 cm: in the example
    box its closed lanes were a point in the middle and the box's ends went unswept (a false
    "empty" with a mug, a ball and a spray can left, docs/empty-the-box.md); it sweeps stretched.
    Every other hand, the Barrett's included, still sweeps closed; each look knows its hand's
    whole extent (`hand_extent`), which turns it along the walls."""
    task, found = load_task(REPO / "tests" / "data" / "empty_the_box" / "blind_look.xml")
    assert found == []
    for factory in every_factory():
        look = translate(task, factory).estd.states_by_name["look"]
        shape = look.hand.params["shape"]
        assert shape == ("extend" if factory.arm.hand.name == "Schunk SDH2" else "closed"), factory.name
        assert look.arm.params["hand_radius"] == round(factory.robot.hand_radius(shape), 6)
        assert look.arm.params["hand_extent"] == tuple(round(e, 6) for e in factory.robot.hand_extent(shape))
    sdh2 = translate(task, create("tombatossals", arm="left")).estd.states_by_name["look"]
    assert sdh2.arm.params["hand_radius"] == pytest.approx(0.05, abs=0.001)


def test_only_a_look_with_stretched_fingers_places_a_top_under_the_half_of_its_tip_that_felt_it():
    """The SDH2's stretched fingers touch down with three fingertips 3.3-4.7 cm off its TCP and
    nothing under it: its look is told its tip is spread (`spread_tip`), and its pinch's
    footprint (the thumb 8.9 cm out), which the look turns towards the room. Every other hand
    looks closed, its tip not spread (docs/empty-the-box.md)."""
    task, found = load_task(REPO / "tests" / "data" / "empty_the_box" / "blind_look.xml")
    assert found == []
    for factory in every_factory():
        look = translate(task, factory).estd.states_by_name["look"]
        assert look.arm.params["spread_tip"] is (look.hand.params["shape"] == "extend"), factory.name
    sdh2 = translate(task, create("tombatossals", arm="left")).estd.states_by_name["look"]
    assert sdh2.arm.params["spread_tip"] is True and sdh2.arm.params["grasp_turn"] == 0.0
    assert sdh2.arm.params["grasp_footprint"][2] == pytest.approx(-0.038, abs=0.001)


def test_vision_is_told_where_the_sdh2_s_pinch_fingertips_and_thumb_come_down_and_the_barrett_s_nothing():
    """The SDH2's pinch closes along its hand's y between two fingertips 4.8-6.8 cm out, 1.1 cm
    either way of the pinch, and its thumb hangs as low 9.0-10.7 cm behind: vision is told both
    (`jaw_band`, `other_tips`) to keep them off what it sees. The Barrett's pinch closes along
    its x: neither. A parallel jaw has its jaws and nothing else."""
    task, found = load_task(EXAMPLES / "empty_the_box_vision.xml")
    assert found == []
    look = {arm: translate(task, create("tombatossals", arm=arm)).estd.states_by_name["look"].arm.params
            for arm in ("left", "right")}
    assert look["left"]["jaw_band"] == pytest.approx((0.048, 0.0676, 0.011), abs=0.001)
    assert look["left"]["other_tips"] == pytest.approx((-0.1075, -0.0895, 0.011), abs=0.001)
    assert not any(look["right"]["jaw_band"]) and not any(look["right"]["other_tips"])
    melfa = translate(task, create("melfa")).estd.states_by_name["look"].arm.params
    assert melfa["jaw_band"][1] > 0.0 and not any(melfa["other_tips"])


def test_robots_claim_the_perception_events_they_map():
    for factory in every_factory():
        events = factory.capabilities.events
        assert {EventType.OBJECT_FOUND, EventType.NOTHING_FOUND, EventType.CONTACT, EventType.NO_CONTACT} <= events
        assert EventType.OUTCOME in events  # the executor's, every robot's


def test_a_named_object_s_weight_is_what_its_transport_checks():
    """The edge leaving a transport of the heavy duck asks the wrist to feel the duck, not the mug."""
    heavy = DUCK.model_copy(update={"weight": 0.8})
    task = Task(known_objects=(MUG, heavy), states=(
        State(name="lift", type=StateType.TRANSPORT, object="duck"), State(name="done", type=StateType.SUCCESS)),
        transitions=(Transition(origin="lift", destination="done", events=(Event(type=EventType.GRASP_STABLE),)),))
    estd = translate(task, create("melfa")).estd
    load = next(leaf for leaf in leaves(estd.transitions[0].events[0].condition) if leaf.kind == "load_held")
    assert load.params["weight"] == 0.4


def test_the_move_to_vision_s_approach_is_for_where_the_pinch_closes_on_each_hand():
    """pick_one's reach goes to the approach in the pinch's preshape: the SDH2 pinches 19 mm off
    its TCP (its description's grasp centre), so its move is told that point; hands that pinch
    on their TCP are not. Every arm's last joint rolls the hand, turning against a turn of the
    hand pointing down, and the move is told so, to take the approach's yaw the way it has room."""
    task, found = load_task(EXAMPLES / "empty_the_box_vision.xml")
    assert found == []
    for factory in every_factory():
        reach = translate(task, factory).estd.states_by_name["take_one_out"].machine.states_by_name["reach"]
        centre = factory.robot.hand.grasp_centres.get("pinch_grasp_preshape", (0.0, 0.0, 0.0))
        assert reach.arm.params["hand_point"] == tuple(round(float(c), 6) for c in centre), factory.name
        assert reach.arm.params["wrist_roll"] == -1.0, factory.name
    sdh2 = translate(task, create("tombatossals", arm="left")).estd.states_by_name["take_one_out"].machine
    assert sdh2.states_by_name["reach"].arm.params["hand_point"] == (0.019, 0.0, 0.0)


def test_the_touch_and_the_pinch_under_it_are_each_hands_own_points():
    """examples/unscrew_by_touch.xml names no hand's offsets: its explore writes where the
    hand's lowest point touched, pads counted (the SDH2's thumb, 38 mm off and 21 mm under
    its TCP; the Barrett's pointing finger's pad tip; a gripper's closed jaws under its TCP), a move to that point puts the lowest point of its
    shape there, under its grasp centre, and the move the unscrew pinches from puts there
    the lower edge of its pads closed to the cap's width, so each TCP stops where its own
    hand says."""
    task, found = load_task(EXAMPLES / "unscrew_by_touch.xml")
    assert found == []
    for factory in every_factory():
        states = translate(task, factory).estd.states_by_name
        robot = factory.robot
        thumb = states["find_cap"].arm.params["hand_point"]
        push = robot.hand.push_posture
        assert thumb == tuple(round(v, 6) for v in (*robot.hand.grasp_centres.get(push, (0.0, 0.0))[:2],
                                                     robot.touch_reach(push))), factory.name
        over = states["open_over_cap"].arm.params["hand_point"]
        centre = robot.hand.grasp_centres.get("pinch_grasp_preshape", (0.0, 0.0, 0.0))
        assert over[:2] == tuple(centre[:2]) and over[2] == round(robot.touch_reach("pinch_grasp_preshape"), 6)
        pinch = states["around_cap"].arm.params["hand_point"]
        pads = states["unscrew_cap"].hand.params.get("pad_reach", over[2])  # a gripper's jaws end with their pads
        assert pinch[:2] == over[:2] and pinch[2] == round(pads + robot.hand.pinch_clearance, 6), factory.name
        assert states["around_cap"].target_offset == (0.0, 0.0, -0.012)
    sdh2 = translate(task, create("tombatossals", arm="left")).estd.states_by_name
    assert sdh2["find_cap"].arm.params["hand_point"] == (-0.038, 0.0, 0.021)
    melfa = translate(task, create("melfa")).estd.states_by_name
    assert melfa["around_cap"].arm.params["hand_point"] == (0.0, 0.0, 0.0238)  # the jaws' tips, 23.8 mm down
    barrett = translate(task, create("tombatossals", arm="right")).estd.states_by_name
    assert barrett["find_cap"].arm.params["hand_point"][2] == 0.011855  # its pad's tip, 4 mm past the link's end
    # a move to a pose (vision's approach) is still for the grasp centre itself: see the test above


def test_free_one_s_drags_take_every_hand_s_lowest_point_to_the_same_heights_over_the_floor():
    """examples/free_one.xml states its drags' heights for the closed hand's lowest point, pads
    counted: a gripper's jaws' ends, a pointing finger's tip (the SDH2's thumb, the Barrett's F3),
    the point its `touch` feels with. Each hand's TCP stops that far over them, so every lowest
    point drags 1.6, 3.6 and 4.6 cm over the box's floor (z 0.01) and the Melfa's TCP goes where
    it went when the heights were its grasp centre's (z 0.05, 0.07, 0.08). Stated for the point
    a closed hand acts at, the SDH2's thumb dragged 4 cm over the floor, at the top of an object
    lying in the box, and moved nothing (docs/empty-the-box.md)."""
    task, found = load_task(EXAMPLES / "free_one.xml")
    assert found == []
    for factory in every_factory():
        states = translate(task, factory).estd.states_by_name
        lowest = states["touch"].arm.params["hand_point"]  # where the closed hand touches, from its TCP
        tcp = [states[name].arm.params["target"][2] for name in ("drag", "tip", "tip_tall")]
        assert [round(z - lowest[2], 6) for z in tcp] == [0.0262, 0.0462, 0.0562], factory.name
    melfa = translate(task, create("melfa")).estd.states_by_name
    assert [melfa[name].arm.params["target"][2] for name in ("drag", "tip", "tip_tall")] == [0.05, 0.07, 0.08]


def _pads_meet(robot, width: float) -> tuple[float, float]:
    """Where the pinch's two pads first come `width` apart, corner to corner, as the hand
    closes from its preshape (a finger's second joint flexing back by what its first
    closes, as the unscrew's hand keeps its pads' slant), scanned in 1.6 mrad steps: the
    lowest of their corners along the approach, from the TCP (m), and the gap found."""
    hand = robot.hand
    start, grasp = (np.asarray(hand.postures[p], float) for p in ("pinch_grasp_preshape", "pinch_grasp"))
    closing = np.array([dof.closing for dof in hand.dofs], float)
    moving = (closing != 0) & ~np.isclose(start, grasp)
    pads = [k for k, pad in enumerate(hand.pads) if any(moving[i] for i in robot.moving_dofs(pad.link))]
    line = robot.closing_line("pinch_grasp_preshape", "pinch_grasp")
    way = np.array([np.cos(line), np.sin(line)])
    opened = np.where(moving, [dof.open for dof in hand.dofs], start)
    closed = np.where(moving, [dof.closed for dof in hand.dofs], start)
    sides = None
    for t in np.linspace(0.0, 1.0, 1500):
        q = opened + t * (closed - opened)
        for k in pads:
            for follower in robot.moving_dofs(hand.pads[k].link):
                if not moving[follower] and closing[follower]:
                    lead = next(i for i in robot.moving_dofs(hand.pads[k].link) if moving[i])
                    q[follower] = start[follower] - closing[follower] * closing[lead] * (q[lead] - start[lead])
        poses = robot.link_poses(robot.hand_joint_targets(q))
        to_hand = np.linalg.inv(poses[robot.tcp.link] @ robot.tcp.origin.matrix())
        corners = [(hand.pads[k].corners @ (to_hand @ poses[hand.pads[k].link] @ hand.pads[k].origin.matrix()).T)[:, :3]
                   for k in pads]
        along = [c[:, :2] @ way for c in corners]
        sides = sides if sides is not None else [np.sign(a.mean() - np.mean([b.mean() for b in along])) for a in along]
        gap = min(a.min() for a, s in zip(along, sides) if s > 0) - max(a.max() for a, s in zip(along, sides) if s < 0)
        if gap <= width:
            return max(float(c[:, 2].max()) for c in corners), gap
    raise AssertionError("the pads never came that near")


def test_every_hand_pinches_a_cap_with_its_pads_at_the_tasks_depth():
    """The unscrew's pinch 12 mm under the felt cap top is where the pads' lower edge goes,
    closed to the cap's 60 mm, not the open preshape's lowest point: a Barrett's curling
    fingers met the cap with their pads' tips 5 mm higher than that point, over a narrow
    cap's top (2 of 8 caps, docs/unscrew-campaign.md), the SDH2's pads 3 mm higher; a
    gripper's jaws end with their pads (unchanged). Each hand's pads, closed from the TCP
    where the translation leaves it, meet the cap within 0.3 mm of 12 mm under its top, but
    the Barrett's, 10 mm: its pads meet the cap tip first, faces turned up, and 12 mm down
    they lifted the jam jar's cap out of the pinch as it rose up its thread (fails on main: 12)."""
    task, _ = load_task(EXAMPLES / "unscrew_by_touch.xml")
    for robot, arm, depth in (("tombatossals", "right", 0.010), ("tombatossals", "left", 0.012)):
        factory = create(robot, arm=arm)
        states = translate(task, factory).estd.states_by_name
        tcp_depth = -states["around_cap"].target_offset[2] - states["around_cap"].arm.params["hand_point"][2]
        edge, gap = _pads_meet(factory.robot, 0.06)
        assert abs(gap - 0.06) < 0.0005 and abs(tcp_depth + edge - depth) < 0.0003, (robot, arm, tcp_depth + edge)
