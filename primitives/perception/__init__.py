"""Perceptual primitives (thesis 3.2, 3.4.3): finding an object to grasp in a container the
robot knows, by one of three approach-vector generators, from its own sensors only."""
