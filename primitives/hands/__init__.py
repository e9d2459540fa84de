"""Hand controllers, one module per kind of hand (thesis 7.3: the hands differ too much
to share their grasps); postures every hand can take live in `posture`."""

from __future__ import annotations

from primitives.robot import HandInfo


def hand_kind(hand: HandInfo) -> str:
    """Which family of grasp controllers fits this hand."""
    if len(hand.dofs) == 1:
        return "parallel_jaw"
    return "multi_finger"
