"""Side grasps (issue 32): grasp-and-lift ATDs whose hand approaches a standing cylinder
horizontally, turned 90 degrees from pointing down, from the front (towards +x, away from
the robot) or from one side (towards +y or -y)."""

from __future__ import annotations

import numpy as np

# The hand's turn away from top-down (docs/atd-format.md) that points its approach axis
# along each direction, keeping its closing axis horizontal.
_FRONT = np.array([[0.0, 0.0, -1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]])  # -90 degrees about y
_YAW = {"+x": 0.0, "+y": 90.0, "-y": -90.0}

OBJECT = (0.10, 0.0, 0.06)  # the cylinder's centre: a bottle 2 cm in radius, 12 cm tall, under the hand at home
GRASP_HEIGHT = 0.09  # m: where the hand closes on it
START = 0.12  # m before the object's axis where the turned hand arrives
ABOVE = 0.12  # m over that where the hand turns first, clear of the object and the table
NEAR = 0.07  # m before it where the guarded preshape ends and the grasp's approach begins

TEMPLATE = """<?xml version="1.0" encoding="UTF-8"?>
<statemachine>
  <object>
    <pose>1 0 0 {ox}  0 1 0 {oy}  0 0 1 {oz}  0 0 0 1</pose>
    <weight>0.2</weight>
    <inertia>2.6e-4 0 0  0 2.6e-4 0  0 0 4.0e-5</inertia>
    <friction>0.8</friction>
    <class>cylinder</class>
    <size>0.02 0.12</size>
  </object>
  <state name="turn" type="move">
    <movement>free</movement>
    <hand_shape>{coming}</hand_shape>
    <path><pose>{over}</pose></path>
  </state>
  <state name="approach" type="move">
    <movement>free</movement>
    <hand_shape>{coming}</hand_shape>
    <path><pose>{start}</pose></path>
  </state>
  <state name="preshape_hand" type="move">
    <movement>guarded</movement>
    <hand_shape>pinch_grasp_preshape</hand_shape>
    <path><pose>{near}</pose></path>
  </state>
  <state name="grasp_object" type="grasp">
    <movement>guarded</movement>
    <hand_shape>pinch_grasp</hand_shape>
  </state>
  <state name="lift_object" type="transport">
    <movement>guarded</movement>
    <hand_shape>pinch_grasp</hand_shape>
    <path><position>{ox} {oy} {lz}</position></path>
  </state>
{put_down}  <state name="success_end" type="success"/>
  <state name="fail_end" type="failure"/>
  <transition origin="turn" destination="approach"><success/></transition>
  <transition origin="approach" destination="preshape_hand"><success/></transition>
  <transition origin="preshape_hand" destination="grasp_object"><success/></transition>
  <transition origin="grasp_object" destination="lift_object"><success/><grasp_stable/></transition>
  <transition origin="lift_object" destination="fail_end"><grasp_lost/></transition>
{after_lift}  <transition origin="turn" destination="fail_end"><timeout>20</timeout></transition>
  <transition origin="approach" destination="fail_end"><timeout>20</timeout></transition>
  <transition origin="preshape_hand" destination="fail_end"><timeout>20</timeout></transition>
  <transition origin="grasp_object" destination="fail_end"><timeout>20</timeout></transition>
  <transition origin="lift_object" destination="fail_end"><timeout>20</timeout></transition>
  <transition origin="turn" destination="fail_end"><error/></transition>
  <transition origin="approach" destination="fail_end"><error/></transition>
  <transition origin="preshape_hand" destination="fail_end"><error/></transition>
  <transition origin="grasp_object" destination="fail_end"><error/></transition>
  <transition origin="lift_object" destination="fail_end"><error/></transition>
</statemachine>
"""


LIFTED = """  <transition origin="lift_object" destination="success_end"><success/><grasp_stable/></transition>
"""
# Put back where it stood, let go and back off along the approach, the hand turned as it held it.
PUT_DOWN = """  <state name="put_down" type="place">
    <movement>guarded</movement>
    <path><position>{ox} {oy} {height}</position></path>
  </state>
  <state name="let_go" type="release">
    <hand_opening>1.0</hand_opening>
  </state>
  <state name="back_off" type="move">
    <movement>guarded</movement>
    <path><pose>{start}</pose></path>
  </state>
"""
PUT_DOWN_EDGES = """  <transition origin="lift_object" destination="put_down"><success/><grasp_stable/></transition>
  <transition origin="put_down" destination="let_go"><success/></transition>
  <transition origin="let_go" destination="back_off"><success/></transition>
  <transition origin="back_off" destination="success_end"><success/></transition>
  <transition origin="put_down" destination="fail_end"><error/></transition>
  <transition origin="back_off" destination="fail_end"><error/></transition>
  <transition origin="put_down" destination="fail_end"><timeout>20</timeout></transition>
  <transition origin="let_go" destination="fail_end"><timeout>20</timeout></transition>
  <transition origin="back_off" destination="fail_end"><timeout>20</timeout></transition>
"""


def turn(direction: str) -> np.ndarray:
    """The hand's turn that points its approach axis along `direction` ('+x', '+y', '-y')."""
    yaw = np.radians(_YAW[direction])
    about_z = np.array([[np.cos(yaw), -np.sin(yaw), 0.0], [np.sin(yaw), np.cos(yaw), 0.0], [0.0, 0.0, 1.0]])
    return about_z @ _FRONT


def _pose(rotation: np.ndarray, at: np.ndarray) -> str:
    rows = [" ".join(f"{v:.9g}" for v in (*rotation[k], at[k])) for k in range(3)]
    return "  ".join(rows + ["0 0 0 1"])


def side_grasp(direction: str, height: float = GRASP_HEIGHT, coming: str = "open", put_down: bool = False) -> str:
    """The grasp-and-lift ATD whose hand approaches the cylinder along `direction`, `height`
    up, in the hand shape `coming` until its preshape; `put_down`: then it puts the cylinder
    back down where it stood (a place), lets go and backs off the way it came."""
    rotation = turn(direction)
    centre = np.array([OBJECT[0], OBJECT[1], height])
    along = rotation @ np.array([0.0, 0.0, -1.0])  # the turned hand's approach axis
    start = _pose(rotation, centre - START * along)
    after = PUT_DOWN.format(ox=OBJECT[0], oy=OBJECT[1], height=height, start=start) if put_down else ""
    return TEMPLATE.format(coming=coming, ox=OBJECT[0], oy=OBJECT[1], oz=OBJECT[2], lz=round(height + 0.12, 6),
                           over=_pose(rotation, centre - START * along + (0.0, 0.0, ABOVE)), start=start,
                           near=_pose(rotation, centre - NEAR * along), put_down=after,
                           after_lift=PUT_DOWN_EDGES if put_down else LIFTED)
