"""Tests of the simulated robots (issue 4)."""
