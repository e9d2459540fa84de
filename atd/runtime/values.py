"""Named values at run time: where a state whose `<target from="v"/>` goes, and how a
sub-task's `<input>`s take the including task's values. Robot-independent, in one place:
a perceptual primitive writes a TCP pose or point (primitives/values.py), so the arm
controller's target is that position, whatever the robot."""

from __future__ import annotations

from typing import Any, Iterator, Mapping, MutableMapping

from atd.model.estd import Controller, EstdState
from primitives.blackboard import ARM_KEYS
from primitives.values import Approach, Contact


class MissingValue(RuntimeError):
    """A state reads a value that holds no target (validation keeps this from happening)."""


def target_of(value: Any) -> tuple[float, float, float]:
    """The TCP position a value stands for: an `Approach`'s pose (its position only: the
    move keeps the hand's yaw, even where vision turned the approach), a `Contact`'s point."""
    if isinstance(value, Approach):
        point = value.pose[:3, 3]
    elif isinstance(value, Contact):
        point = value.point
    else:
        raise MissingValue(f"it holds {type(value).__name__ if value is not None else 'nothing'}, not an approach "
                           "or a contact")
    x, y, z = (round(float(v), 6) for v in point)
    return (x, y, z)


def targeted(arm: Controller, target: tuple[float, float, float]) -> Controller:
    """The arm controller with its `target` set."""
    return arm.model_copy(update={"params": {**arm.params, "target": target}})


def arm_for(state: EstdState, memory: Mapping[str, Any]) -> Controller | None:
    """The state's arm controller as it runs now: with its target read from memory when the
    state takes it from a named value."""
    if state.arm is None or state.target_from is None:
        return state.arm
    try:
        return targeted(state.arm, target_of(memory.get(state.target_from)))
    except MissingValue as exc:
        raise MissingValue(f"state '{state.name}' takes its target from '{state.target_from}': {exc}") from None


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
