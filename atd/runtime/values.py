"""Named values at run time: where a state whose `<target from="v"/>` goes, and how a
sub-task's `<input>`s take the including task's values. Robot-independent, in one place:
a perceptual primitive writes a TCP pose or point (primitives/values.py), so the arm
controller's target is that position (and a pose's yaw), whatever the robot."""

from __future__ import annotations

import math
from typing import Any, Iterator, Mapping, MutableMapping

import numpy as np

from atd.model.controllers import ARM_CONTROLLERS
from atd.model.estd import Controller, EstdState
from primitives.blackboard import ARM_KEYS
from primitives.values import Approach, Contact


class MissingValue(RuntimeError):
    """A state reads a value that holds no target (validation keeps this from happening)."""


def target_of(value: Any) -> dict[str, Any]:
    """The arm controller parameters a value sets: an `Approach`'s pose, its position as the
    `target` and its hand x as the `yaw` (deg; the move turns the hand about the vertical, so
    the jaws close the way vision chose; to that yaw itself, not `either_way`, where the
    approach's half turn matters), a `Contact`'s point as the `target` only."""
    if isinstance(value, Approach):
        x = value.pose[:3, 0]
        turn = {} if value.either_way else {"either_way": False}
        return {"target": _rounded(value.pose[:3, 3]), "yaw": round(math.degrees(math.atan2(x[1], x[0])), 6), **turn}
    if isinstance(value, Contact):
        return {"target": _rounded(value.point)}
    raise MissingValue(f"it holds {type(value).__name__ if value is not None else 'nothing'}, not an approach "
                       "or a contact")


def _rounded(point: np.ndarray) -> tuple[float, float, float]:
    x, y, z = (round(float(v), 6) for v in point)
    return (x, y, z)


def targeted(arm: Controller, target: Mapping[str, Any]) -> Controller:
    """The arm controller with the parameters a target sets (`target_of`) that it takes: a
    place or a slide goes to the position, only a move turns the hand to a yaw."""
    takes = ARM_CONTROLLERS[arm.name].params
    return arm.model_copy(update={"params": {**arm.params, **{k: v for k, v in target.items() if k in takes}}})


def offset_by(target: dict[str, Any], offset: tuple[float, float, float] | None) -> dict[str, Any]:
    """The parameters a value sets with its position moved by the state's `<target offset>`
    (m, world frame): a place known relative to what was found, as a pinch a known depth
    below the top an explore felt."""
    if offset is None:
        return target
    return {**target, "target": _rounded(np.add(target["target"], offset))}


def arm_for(state: EstdState, memory: Mapping[str, Any]) -> Controller | None:
    """The state's arm controller as it runs now: with its target read from memory (and
    offset as the state says) when the state takes it from a named value."""
    if state.arm is None or state.target_from is None:
        return state.arm
    try:
        return targeted(state.arm, offset_by(target_of(memory.get(state.target_from)), state.target_offset))
    except MissingValue as exc:
        raise MissingValue(f"state '{state.name}' takes its target from '{state.target_from}': {exc}") from None


def topped(arm: Controller | None, state: EstdState, memory: Mapping[str, Any]) -> Controller | None:
    """A grasp's arm controller as it runs now: where the state reads the object's top from a
    value (`<object_top from>`), with `object_top` set to the top that value's approach saw,
    if the controller takes one; unchanged where the approach saw none (random blind)."""
    if arm is None or state.top_from is None or "object_top" not in ARM_CONTROLLERS[arm.name].params:
        return arm
    value = memory.get(state.top_from)
    if not isinstance(value, Approach):
        raise MissingValue(f"state '{state.name}' takes the object's top from '{state.top_from}': it holds "
                           f"{type(value).__name__ if value is not None else 'nothing'}, not an approach")
    if value.top is None:
        return arm
    return arm.model_copy(update={"params": {**arm.params, "object_top": round(value.top, 6)}})


def bind_inputs(state: EstdState, memory: MutableMapping[str, Any]) -> None:
    """A sub-task state starting: each of the sub-task's inputs holds the value its parent
    names (`<input name="i" from="v"/>`), by the sub-task's own name."""
    for name, source in state.inputs.items():
        memory[name] = memory.get(source)


class ArmMemory(MutableMapping[str, Any]):
    """One arm's view of a two-arm run's memory: what it learnt of itself (`ARM_KEYS`: its
    empty hand's load, its last twist) its own, the named values shared with the other arm
    (a value one role writes, the other may read)."""

    def __init__(self, shared: MutableMapping[str, Any]) -> None:
        self.shared = shared
        self.own: dict[str, Any] = {}

    def _store(self, key: str) -> MutableMapping[str, Any]:
        return self.own if key in ARM_KEYS else self.shared

    def __getitem__(self, key: str) -> Any:
        return self._store(key)[key]

    def __setitem__(self, key: str, value: Any) -> None:
        self._store(key)[key] = value

    def __delitem__(self, key: str) -> None:
        del self._store(key)[key]

    def __iter__(self) -> Iterator[str]:
        yield from self.own
        yield from (k for k in self.shared if k not in ARM_KEYS)

    def __len__(self) -> int:
        return sum(1 for _ in self)
