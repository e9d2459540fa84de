"""The three translation rules and full traceability, over generated valid ATDs, for every factory."""

from __future__ import annotations

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from atd.model import HandShape, Pose, State, StateType, Task, Waypoint
from atd.model.diagnostics import Severity
from atd.model.estd import leaves
from tests.model.strategies import tasks
from tests.translator.helpers import every_factory
from translator import check_rules, translate

FACTORIES = every_factory()


def _into_work_area(v: tuple[float, ...]) -> tuple[float, float, float]:
    """Map generated coordinates in [-1, 1] onto the shared work area, 3..25 cm above the table."""
    x, y, z = v[:3] if len(v) == 3 else (v[3], v[7], v[11])
    return (0.1 + 0.1 * x, 0.15 * y, 0.14 + 0.11 * z)


def reachable(task: Task, plain: bool) -> Task:
    """The same graph with every target and the object in the work area; `plain` also drops
    parameter overrides, hook shapes, obstacles (a hand with no room around the object),
    objects over 2 kg (Baxter's payload is 2.2 kg) and friction under 0.1 (2 kg would need
    over 1,000 N of grasp force at 0.016), which some robots rightly refuse."""
    def fix(state: State) -> State:
        update: dict = {"path": tuple(Waypoint(kind="position", values=_into_work_area(w.values))
                                      for w in state.path)}
        if plain:
            update["parameters"] = {}
            for field in ("hand_shape", "preshape"):
                if getattr(state, field) in (HandShape.HOOK_GRASP, HandShape.HOOK_GRASP_PRESHAPE):
                    update[field] = HandShape.POWER_GRASP
        return state.model_copy(update=update)

    obj = task.object
    if obj is not None and obj.pose is not None:
        obj = obj.model_copy(update={"pose": Pose.from_position(_into_work_area(obj.pose.matrix))})
    if plain and obj is not None and obj.weight is not None:
        obj = obj.model_copy(update={"weight": min(obj.weight, 2.0)})
    if plain and obj is not None and obj.friction is not None:
        obj = obj.model_copy(update={"friction": max(obj.friction, 0.1)})
    update = {"states": tuple(fix(s) for s in task.states), "object": obj}
    if plain:
        update["environment"] = None
    return task.model_copy(update=update)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(tasks(), st.booleans())
def test_rules_and_traceability_hold_or_translation_is_refused_with_reasons(task, plain):
    task = reachable(task, plain)
    for factory in FACTORIES:
        result = translate(task, factory)
        errors = [d for d in result.diagnostics if d.severity is Severity.ERROR]
        arms_enough = len(task.roles) <= len(factory.arms)
        if plain and arms_enough:  # nothing left that any robot should refuse
            assert result.ok, (factory.name, factory.arm.name, [d.render() for d in errors])
        if not arms_enough:  # refused for its arms alone, at the role without one
            assert [d.code for d in errors] == ["TRN005"] and "'worker'" in errors[0].message
        if not result.ok:
            assert errors and all(d.code in {"TRN001", "TRN002", "TRN004", "TRN005"} and factory.name in d.message
                                  for d in errors)
            continue
        estd = result.estd
        assert sorted(estd.roles) == sorted(r.name for r in task.roles)  # roles: each bound, each on its own arm
        assert len(set(estd.roles.values())) == len(estd.roles)
        assert all(s.robot_arm == estd.roles[task.role_of(task.states_by_name[s.name])]
                   for s in estd.states if not s.type.is_end and task.roles)
        assert check_rules(task, estd) == []
        assert [s.atd for s in estd.states] == [s.name for s in task.states]  # rule 1
        assert [t.atd for t in estd.transitions] == list(task.transition_ids)  # rule 2
        for atd_edge, edge in zip(task.transitions, estd.transitions):  # rule 3 + trace
            assert [e.type for e in edge.events] == [e.type for e in atd_edge.events]
            for event in edge.events:
                assert event.atd.startswith(f"{edge.atd}/{event.type.value}")
                assert leaves(event.condition) and all(c.atd == event.atd for c in leaves(event.condition))
        for state in estd.states:
            if not state.type.is_end:
                assert state.arm is not None and state.hand is not None and state.primitive


def test_property_generator_also_covers_every_primitive():
    """The generated tasks above must reach every arm and hand primitive the strategy knows."""
    kinds = set()

    @settings(max_examples=60, deadline=None, database=None)
    @given(tasks())
    def collect(task):
        kinds.update(s.type for s in task.states)

    collect()
    assert {StateType.MOVE, StateType.TRANSPORT, StateType.PLACE, StateType.PUSH, StateType.GRASP,
            StateType.RELEASE} <= kinds


def test_a_transport_whose_object_no_grasp_force_could_carry_is_refused_with_the_fix() -> None:
    """Found by the property above: a lone transport of 4 kg at friction 1/64 would ask each
    pad for 1,256 N, and the Melfa's translation ended in the translator's own refusal of a
    defective ESTD (TRN100), not in the factory's reasons."""
    states = (State(name="carry", type=StateType.TRANSPORT, path=(Waypoint(kind="position", values=(0.1, 0.0, 0.2)),)),
              State(name="done", type=StateType.SUCCESS))
    task = Task(known_objects=({"weight": 4.0, "friction": 0.015625},), states=states,
                transitions=({"origin": "carry", "destination": "done", "events": ({"type": "success"},)},))
    for factory in FACTORIES:
        result = translate(task, factory)
        codes = {d.code for d in result.diagnostics if d.severity is Severity.ERROR}
        assert not result.ok and "TRN100" not in codes, (factory.name, codes)
