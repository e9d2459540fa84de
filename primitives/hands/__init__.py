"""Hand controllers, one module per kind of hand (thesis 7.3: the hands differ too much
to share their grasps); postures every hand can take live in `posture`."""

from __future__ import annotations

from primitives.hands import barrett, sdh2
from primitives.robot import HandInfo


def hand_kind(hand: HandInfo) -> str:
    """Which family of grasp controllers fits this hand, told by its DOFs."""
    if len(hand.dofs) == 1:
        return "parallel_jaw"
    for kind, dofs in (("barrett", barrett.DOFS), ("sdh2", sdh2.DOFS)):
        if hand.dofs == dofs:
            return kind
    raise ValueError(f"no hand controllers for a hand with the DOFs {', '.join(hand.dofs)}")
