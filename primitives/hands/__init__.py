"""Hand controllers, one module per kind of hand (thesis 7.3: a parallel jaw and a hand
with fingers of its own grasp too differently to share one controller); postures every
hand can take live in `posture`. What differs between hands of one kind (where the
fingers stand, which postures they make) comes from the robot's description."""

from __future__ import annotations

from primitives.robot import HandInfo


def hand_kind(hand: HandInfo) -> str:
    """Which family of grasp controllers fits this hand: one DOF moves both jaws of a
    parallel gripper; a multi-finger hand (the Barrett, the SDH2) has pads on at least two
    fingers that move on DOFs of their own."""
    if len(hand.dofs) == 1:
        return "parallel_jaw"
    if len({pad.dofs for pad in hand.pads if pad.dofs}) >= 2:
        return "multi_finger"
    raise ValueError(f"no hand controllers for a hand with the DOFs {', '.join(hand.dofs)}: "
                     "it has neither one jaw DOF nor tactile pads on two fingers")
