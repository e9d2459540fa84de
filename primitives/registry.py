"""From ESTD names to running objects: the one place that knows which class implements
each controller and condition of the vocabulary (`atd.model.controllers`).

Parameters reach a controller or condition with the vocabulary's defaults filled in,
then the ESTD's own values on top. Arm controllers serve every robot; hand controllers
are looked up by the kind of hand (`primitives.hands.hand_kind`), so an ESTD asking a
gripper for a three-finger grasp fails with a message instead of misbehaving.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Callable, Mapping

from atd.model.controllers import ARM_CONTROLLERS, CONDITIONS, HAND_CONTROLLERS, defaults
from atd.model.estd import Condition as Leaf
from atd.model.estd import Controller as Use
from primitives.arm.explore import Explore
from primitives.arm.grasp import NaiveGraspApproach
from primitives.arm.jaw_grasp import JawGraspCorrection
from primitives.arm.move import CartesianMove, Hold, Push
from primitives.arm.robust_approach import RobustGraspApproach
from primitives.arm.slide import Slide
from primitives.arm.surface import Place, ReleaseRetreat
from primitives.arm.unscrew import UnscrewArm
from primitives.base import Condition, Context, Controller, Status
from primitives.conditions import (
    Fault,
    FingersPressing,
    FingersStill,
    Gripper,
    LoadHeld,
    Perceived,
    Range,
    SimulationUnstable,
    SlipWatched,
    StatusIs,
    SubtaskEndedIn,
    TactileForce,
    TactileLoadChange,
    Timeout,
    WristForceAbove,
)
from primitives.hands import hand_kind
from primitives.hands.multi_finger import NaiveGraspHand
from primitives.hands.parallel_jaw import CloseUntilForce, NaiveJawGrasp, Squeeze
from primitives.hands.posture import HandShape, HoldPosition, OpenTo
from primitives.hands.robust_grasp import RobustGraspHand
from primitives.hands.unscrew import UnscrewHand
from primitives.hands.unscrew_jaws import UnscrewJaws
from primitives.perception.perceive import perceive
from primitives.values import Approach, NothingFound


class BuildError(ValueError):
    """An ESTD names something this robot cannot run; the message says what and why."""


ControllerClass = Callable[[Context], Controller]
ConditionMaker = Callable[[Context, tuple[str, ...]], Condition]

ARM: Mapping[str, ControllerClass] = {
    "hold": Hold,
    "cartesian_move": CartesianMove,
    "push": Push,
    "place": Place,
    "slide": Slide,
    "release_retreat": ReleaseRetreat,
    "robust_grasp_approach": RobustGraspApproach,
    "naive_grasp_approach": NaiveGraspApproach,
    "jaw_grasp_correction": JawGraspCorrection,
    "explore": Explore,
    "perceive": perceive,
    "unscrew_arm": UnscrewArm,
}

_POSTURES: Mapping[str, ControllerClass] = {"hold_position": HoldPosition, "hand_shape": HandShape, "open_to": OpenTo}

HANDS: Mapping[str, Mapping[str, ControllerClass]] = {
    "parallel_jaw": {**_POSTURES, "close_until_force": CloseUntilForce, "squeeze": Squeeze,
                     "naive_grasp_hand": NaiveJawGrasp, "unscrew_jaws": UnscrewJaws},
    "multi_finger": {**_POSTURES, "robust_grasp_hand": RobustGraspHand, "naive_grasp_hand": NaiveGraspHand,
                     "unscrew_hand": UnscrewHand},
}


def _status(which: str, status: Status) -> ConditionMaker:
    return lambda ctx, sensors: StatusIs(ctx, sensors, which, status)


def _hand_streams(ctx: Context) -> tuple[str, ...]:
    return ("tactile", "range") if ctx.info.has_range else ("tactile",)


CONDITION_KINDS: Mapping[str, ConditionMaker] = {
    "arm_done": _status("arm", Status.DONE),
    "hand_done": _status("hand", Status.DONE),
    "arm_error": _status("arm", Status.ERROR),
    "hand_error": _status("hand", Status.ERROR),
    "subtask_succeeded": _status("subtask", Status.DONE),
    "subtask_failed": _status("subtask", Status.ERROR),
    "subtask_ended_in": SubtaskEndedIn,
    "arm_fault": lambda ctx, sensors: Fault(ctx, sensors, "arm", ("joints", "wrench")),
    "hand_fault": lambda ctx, sensors: Fault(ctx, sensors, "hand", _hand_streams(ctx)),
    "simulation_unstable": SimulationUnstable,
    "timeout": Timeout,
    "tactile_force_above": lambda ctx, sensors: TactileForce(ctx, sensors, above=True),
    "tactile_force_below": lambda ctx, sensors: TactileForce(ctx, sensors, above=False),
    "tactile_load_change": TactileLoadChange,
    "load_held": LoadHeld,
    "fingers_still": FingersStill,
    "fingers_pressing": FingersPressing,
    "slip_watched": SlipWatched,
    "wrist_force_above": WristForceAbove,
    "gripper_force_above": lambda ctx, sensors: Gripper(ctx, sensors, "force", above=True),
    "gripper_force_below": lambda ctx, sensors: Gripper(ctx, sensors, "force", above=False),
    "gripper_opening_above": lambda ctx, sensors: Gripper(ctx, sensors, "opening", above=True),
    "gripper_opening_below": lambda ctx, sensors: Gripper(ctx, sensors, "opening", above=False),
    "range_below": lambda ctx, sensors: Range(ctx, sensors, above=False),
    "range_above": lambda ctx, sensors: Range(ctx, sensors, above=True),
    "object_found": lambda ctx, sensors: Perceived(ctx, sensors, Approach),
    "nothing_found": lambda ctx, sensors: Perceived(ctx, sensors, NothingFound),
}


def build_controller(use: Use, role: str, ctx: Context) -> Controller:
    """The controller an ESTD state names for its arm or hand, ready to `start`."""
    specs = ARM_CONTROLLERS if role == "arm" else HAND_CONTROLLERS
    if use.name not in specs:
        raise BuildError(f"'{use.name}' is not an {role} controller of the ESTD vocabulary")
    if role == "arm":
        table = ARM
    else:
        try:
            kind = hand_kind(ctx.info.hand)
        except ValueError as exc:
            raise BuildError(f"the {ctx.info.name}: {exc}") from None
        table = HANDS[kind]
        if use.name not in table:
            raise BuildError(f"the {ctx.info.name} hand ({kind.replace('_', ' ')}) has no '{use.name}' controller; "
                             f"it has: {', '.join(sorted(table))}")
    params = {**defaults(specs[use.name].params), **use.params}
    try:
        return table[use.name](replace(ctx, params=params))
    except (KeyError, ValueError) as exc:
        raise BuildError(f"{role} controller '{use.name}' on the {ctx.info.name}: {exc}") from None


def build_condition(leaf: Leaf, ctx: Context) -> Condition:
    """The condition an ESTD leaf names, ready to `start`."""
    spec = CONDITIONS.get(leaf.kind)
    if spec is None:
        raise BuildError(f"'{leaf.kind}' is not a condition of the ESTD vocabulary")
    params = {**defaults(spec.params), **leaf.params}
    try:
        return CONDITION_KINDS[leaf.kind](replace(ctx, params=params), tuple(leaf.sensors))
    except (KeyError, ValueError) as exc:
        raise BuildError(f"condition '{leaf.kind}' on the {ctx.info.name}: {exc}") from None
