"""Trial campaigns: many runs of tasks under perturbed truth, each judged by the simulator.

A campaign sits beside the CLI, above the runtime: it drives runs and reads the
simulator's ground truth, and never reaches into primitives.
"""
