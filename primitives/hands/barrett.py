"""The Barrett BH8-280 (Tombatossals' right hand, thesis A.1.2): F1 and F2 on a spread
axis either side of the palm centre, F3 (the thumb) opposite them."""

from primitives.hands.multi_finger import FingerLayout, RobustGraspHand

DOFS = ("spread", "f1", "f2", "f3")

# Finger bases in the hand frame, m (factories/tombatossals/description.py: knuckles at x = -/+25 mm,
# the thumb 50 mm along -y).
LAYOUT: FingerLayout = {"tactile_f1": (-0.025, 0.0), "tactile_f2": (0.025, 0.0), "tactile_f3": (0.0, -0.05)}


class BarrettRobustGrasp(RobustGraspHand):
    layout = LAYOUT
