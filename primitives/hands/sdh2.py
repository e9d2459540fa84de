"""The Schunk SDH2 (Tombatossals' left hand, thesis A.1.2): two fingers on a common
rotation axis and a fixed thumb, each with a proximal and a distal joint."""

from primitives.hands.multi_finger import FingerLayout, RobustGraspHand

DOFS = ("rotation", "f1_proximal", "f1_distal", "f2_proximal", "f2_distal", "thumb_proximal", "thumb_distal")

# Finger bases in the hand frame, m (the SDH2 manual's layout, as in factories/tombatossals/description.py).
LAYOUT: FingerLayout = {"tactile_f1": (0.019, 0.033), "tactile_f2": (0.019, -0.033), "tactile_f3": (-0.038, 0.0)}  # f3: thumb


class Sdh2RobustGrasp(RobustGraspHand):
    layout = LAYOUT
