"""D5's finger-extension check of a closed three-finger grasp (D5 3.3.2-3.3.3): where the
fingers stopped tells where the object is, and whether the hand holds it as it should.

A finger's extension is how far its contact lies from the hand's centre. D5's quality
Q = (e1 - e2)^2 + (e2 - e3)^2 + (e3 - e1)^2 (Eq. 3.1) is zero when every finger reaches
equally far, and the two corrections bring it there: the position correction Z (Eq. 3.3),
half the difference between the two sides' reach, moves the hand along the line the
fingers squeeze on; the orientation correction alpha = atan((e2 - e1) / i) (Eq. 3.2)
turns it about the approach axis when two fingers press from the same side at different
extensions. The appendix paper adds the move that brings the object onto the palm's
centre across that line; the pads' centre of pressure gives it.

Here the contacts come from the hand's forward kinematics (`HandInfo.pad_surfaces`) and
the tactile images, so the check serves any hand that reports its pads (`ExtensionGauge`
says how it reads them). Extensions are in units of the preshape's reach, so D5's bound
Q < 0.01 carries over to hands of other sizes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from atd.model.frames import rectangle_corners
from primitives.robot import HandInfo, Readings


@dataclass(frozen=True)
class ExtensionCheck:
    """The check of one closed grasp; `shift` (x, y, 0) and `turn` (rad about the approach
    axis), in the hand frame, move the hand to centre the object."""

    quality: float  # D5's Q, extensions in units of the preshape's reach
    shift: np.ndarray
    turn: float


def pad_corners(hand: HandInfo, hand_q: np.ndarray, pads: list[int]) -> np.ndarray:
    """The four corners of each pad's sensing surface with the hand at `hand_q`: (pads, 4, 3), hand frame."""
    corners = []
    for surface, k in zip(hand.pad_surfaces(hand_q)[pads], pads):
        corners.append((rectangle_corners(hand.pads[k].half_size) @ surface.T)[:, :3])
    return np.array(corners)


def on_side_row(hand: HandInfo, readings: Readings, k: int) -> bool:
    """Pad k presses with one of its two outermost rows across its finger and nothing else:
    it touches what lies beside it with its side edge."""
    image = readings.taxels.get(hand.pads[k].name)
    if image is None:
        return False
    rows = np.flatnonzero(image.sum(axis=1) > 0.0)
    return len(rows) > 0 and (rows[0] == rows[-1] == 0 or rows[0] == len(image) - 1)


def contact_points(hand: HandInfo, readings: Readings, pads: list[int]) -> np.ndarray:
    """Where each pad touches, hand frame: its centre of pressure, or its centre without an image."""
    points = []
    for surface, k in zip(hand.pad_surfaces(readings.hand_q)[pads], pads):
        image = readings.taxels.get(hand.pads[k].name)
        local = np.zeros(2)
        if image is not None and image.sum() > 0.0:
            rows, cols = image.shape
            half = np.asarray(hand.pads[k].half_size)
            cell = np.array([image.sum(axis=0) @ (np.arange(cols) + 0.5) / cols,
                             image.sum(axis=1) @ (np.arange(rows) + 0.5) / rows]) / image.sum()
            local = (2.0 * cell - 1.0) * half
        points.append((surface @ np.array([*local, 0.0, 1.0]))[:3])
    return np.array(points)


class ExtensionGauge:
    """Measures finger extensions for one grasp, against the hand opened in its preshape:
    the squeeze line is the way the grasping pads face there (opposed fingers face each
    other), each finger's side is the way its pad faces along it, the hand's centre lies
    midway between the two sides' pads, and the reach is how far they stand from it."""

    def __init__(self, hand: HandInfo, pads: list[int], preshape: np.ndarray) -> None:
        self.hand, self.pads = hand, pads
        surfaces = hand.pad_surfaces(preshape)[pads]
        facing = surfaces[:, :2, 2] / np.maximum(np.linalg.norm(surfaces[:, :2, 2], axis=1, keepdims=True), 1e-9)
        self.line = np.linalg.eigh(facing.T @ facing)[1][:, -1]
        self.across = np.array([-self.line[1], self.line[0]])
        self.side = np.sign(facing @ self.line)
        opened = surfaces[:, :2, 3]
        along = opened @ self.line
        middle = np.mean(self._side_means(along))
        self.centre = middle * self.line + float((opened @ self.across).mean()) * self.across
        self.reach = max(float(np.abs(along - middle).mean()), 1e-3)

    def _side_means(self, along: np.ndarray) -> list[float]:
        """The mean of `along` over each side's fingers, for the sides that have any."""
        return [float(along[self.side == s].mean()) for s in (1.0, -1.0) if (self.side == s).any()]

    def gap(self, hand_q: np.ndarray) -> float:
        """How near the two sides' pads come to each other along the squeeze line (m),
        corner to corner: the widest object the fingers could still close on (a Barrett's
        curled pinch meets the object with its pads' tips). Infinite for a grasp with one side."""
        if not ((self.side > 0).any() and (self.side < 0).any()):
            return np.inf
        near = []
        for corners, side in zip(pad_corners(self.hand, hand_q, self.pads), self.side):
            along = corners[:, :2] @ self.line
            near.append(along.max() if side > 0 else along.min())
        near = np.array(near)
        return float(near[self.side < 0].min() - near[self.side > 0].max())

    def check(self, readings: Readings) -> ExtensionCheck:
        """D5's Q, Z and alpha (and the centring across), from where the pads touch now."""
        points = contact_points(self.hand, readings, self.pads)
        offsets = points[:, :2] - self.centre
        along, across = offsets @ self.line, offsets @ self.across
        extension = np.abs(along) / self.reach
        quality = float(sum((a - b) ** 2 for i, a in enumerate(extension) for b in extension[i + 1:]))
        sides = self._side_means(along)
        z = 0.5 * sum(sides) if len(sides) == 2 else 0.0  # Eq. 3.3: the two sides straddle the object
        turn = 0.0
        for s in (1.0, -1.0):  # Eq. 3.2, for a side with two fingers
            mine = np.flatnonzero(self.side == s)
            spacing = float(across[mine[1]] - across[mine[0]]) if len(mine) == 2 else 0.0
            if abs(spacing) > 1e-6:
                turn = float(np.arctan((along[mine[0]] - along[mine[1]]) / spacing))
        shift = z * self.line + float(across.mean()) * self.across
        return ExtensionCheck(quality, np.array([*shift, 0.0]), turn)
