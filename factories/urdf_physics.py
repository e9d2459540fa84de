"""A URDF link's mass and inertia, checked as a simulator needs them: a body a joint moves
has a positive mass and an inertia some rigid body could have. MuJoCo refuses anything
else when it compiles the model, and PyBullet simulates it wrongly without a word, so the
import says so first, at the URDF's line.
"""

from __future__ import annotations

import numpy as np

ROUNDING = 1e-9  # of the summed moments: what the triangle inequality forgives a URDF's printed digits

Problem = tuple[str, str]
"""What is wrong, and how to fix it."""


def mass_problem(link: str, mass: float, moving: bool) -> Problem | None:
    """Why `mass` (kg) cannot be the link's: negative, or zero on a link a joint moves."""
    if mass < 0 or (moving and mass == 0):
        frame = "" if moving else " (0 only for a frame welded to its parent)"
        return f"link '{link}' has a mass of {mass:g} kg", f"give its mass in kg, above 0{frame}"
    return None


def inertia_problem(link: str, tensor: np.ndarray) -> Problem | None:
    """Why the 3x3 inertia `tensor` (kg m^2, about the centre of mass) cannot be a body's:
    a principal moment not above 0, or one larger than the other two together."""
    low, middle, high = np.linalg.eigvalsh(tensor)
    moments = f"{low:.3g}, {middle:.3g}, {high:.3g} kg m^2"
    if low <= 0:
        return (f"link '{link}' has an inertia whose principal moments ({moments}) are not all above 0",
                "give ixx, iyy and izz above 0, about the centre of mass, with products smaller than they are")
    if low + middle < high - ROUNDING * (low + middle + high):
        return (f"link '{link}' has principal moments of inertia ({moments}) no rigid body has: the largest is "
                "more than the other two together", "correct the inertia (A + B >= C for its principal moments)")
    return None
