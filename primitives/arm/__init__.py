"""Arm controllers, shared by every robot (thesis 7.3 ran the same Cartesian controllers
on both arms): they command TCP twists and read the wrist wrench."""
