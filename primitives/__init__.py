"""Primitives: controllers and conditions that act on a robot only through `primitives.robot`."""
