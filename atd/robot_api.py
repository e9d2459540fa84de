"""The one module a robot package imports from: `from atd.robot_api import ...`.

A robot is a package with a factory (how the abstract primitives and events become
controllers and conditions on it), a description (its links, joints, hand, pads and
sensors, which both simulators are built from) and a config.toml of tuned values; the
guide is docs/writing-a-robot.md.

Why `atd.robot_api` and not `factories` or `primitives`: those top-level names are generic
and may be taken by any other installed distribution, and where this project keeps its
code is its own business; `atd` is this distribution's name. Everything here is
re-exported unchanged, so code importing from `factories.*` keeps working, and a name
listed in `__all__` keeps its meaning.

The two hand types have one name each here: `Hand` is what the factory declares (the
shapes it makes, for translation), `HandModel` the physical hand of the description
(`factories.description.Hand`: DOFs, pads, postures).
"""

from atd.model.controllers import SensorKind
from atd.model.task import ObjectInfo, State
from atd.model.vocabulary import EventType, HandShape, Movement, StateType
from factories.base import (
    PARALLEL_JAW_SHAPES,
    Arm,
    ConditionNode,
    Factory,
    Hand,
    MappingContext,
    MappingRow,
    NodeMapping,
    Sensor,
    Unmappable,
    all_of,
    any_of,
    grasp_width,
    obstacle_params,
    parallel_jaw_closest,
)
from factories.description import (
    DepthCamera,
    FingerPad,
    HandDof,
    Joint,
    Link,
    Origin,
    RobotDescription,
    SensorModel,
    Servo,
    Shape,
    Site,
    looking_at,
)
from factories.description import Hand as HandModel
from factories.borrowed import installed_hand
from factories.home import HOME_TCP, with_home
from factories.kinds import MultiFingerFactory, ParallelJawFactory
from factories.urdf import UrdfError, UrdfModel, read_urdf
from factories.urdf_hand import urdf_parallel_jaw
from factories.parts import DARK, METAL, JawSpec, box, capsule, cylinder, parallel_jaw

__all__ = [
    # the factory: what it declares and answers
    "Factory", "ParallelJawFactory", "MultiFingerFactory", "Arm", "Hand", "Sensor", "SensorKind", "MappingRow", "MappingContext", "NodeMapping",
    "ConditionNode", "Unmappable", "all_of", "any_of", "obstacle_params", "grasp_width",
    "PARALLEL_JAW_SHAPES", "parallel_jaw_closest",
    # what it is asked about
    "State", "StateType", "EventType", "HandShape", "Movement", "ObjectInfo",
    # the description
    "RobotDescription", "Link", "Joint", "Servo", "Shape", "Origin", "Site", "HandModel", "HandDof",
    "FingerPad", "SensorModel", "DepthCamera", "looking_at",
    # helpers for descriptions
    "box", "capsule", "cylinder", "JawSpec", "parallel_jaw", "METAL", "DARK", "with_home", "HOME_TCP",
    "installed_hand", "read_urdf", "UrdfModel", "UrdfError", "urdf_parallel_jaw",
]
