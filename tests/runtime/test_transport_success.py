"""A transport succeeds only with its object: an arm that arrives with an empty hand has
carried nothing, so the task must not end `succeeded` (issue 10, events that tell the
truth). Before this, a transport's success was its arm and hand controllers done."""

from __future__ import annotations

import pytest

from atd.model import has_errors, load_task
from atd.runtime.session import Run
from factories.registry import create
from translator import translate

EMPTY_HANDED = """
    <statemachine>
      <object>
        <pose>1 0 0 0.10  0 1 0 0.0  0 0 1 0.04  0 0 0 1</pose>
        <weight>0.15</weight>
        <class>cylinder</class>
        <size>0.02 0.08</size>
      </object>
      <state name="approach" type="move"><movement>free</movement><hand_shape>open</hand_shape></state>
      <state name="carry" type="transport">
        <movement>guarded</movement>
        <path><position>0.10 0.0 0.20</position></path>
      </state>
      <state name="done" type="success"/>
      <state name="failed" type="failure"/>
      <transition origin="approach" destination="carry"><success/></transition>
      <transition origin="carry" destination="done"><success/></transition>
      <transition origin="carry" destination="failed"><timeout>4</timeout></transition>
      <transition origin="approach" destination="failed"><timeout>20</timeout></transition>
    </statemachine>
"""


@pytest.mark.parametrize("engine", ["mujoco", "pybullet"])
@pytest.mark.parametrize(("robot", "arm"), [("melfa", "main"), ("tombatossals", "right")])
def test_a_transport_that_arrives_empty_handed_does_not_succeed(atd_file, robot: str, arm: str, engine: str) -> None:
    task, found = load_task(atd_file(EMPTY_HANDED))
    assert task is not None and not has_errors(found), found
    factory = create(robot, arm)
    estd = translate(task, factory).estd
    assert estd is not None
    run = Run(estd, factory, engine=engine, seed=0)
    outcome = run.execute()
    arrived = [r for r in run.trace.records if r["type"] == "event" and r["state"] == "carry"]
    assert not outcome.succeeded, outcome.summary
    assert outcome.end_state == "failed" and arrived[-1]["event"] == "timeout", outcome.summary
