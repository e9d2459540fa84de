"""Where a campaign's drawn worlds leave their objects: how far each settled object lies from
the box's inner walls (thesis 3.4.3 assumes "some clearance between the objects and the sides
of the box"; an object against a wall leaves a finger no room beside it).

Builds each trial's world as a campaign's worker does (the objects dropped and settled by the
engine; the robot is built but never moved) and prints, per trial, each object's gap: the
least distance, along the box's x or y, from its horizontal extent to an inner wall. Spheres
and cylinders are measured exactly, boxes and meshes by their turned bounding box (a mesh's
gap is a lower bound). Then the share of objects and of trials under 0.5, 1 and 2 cm:

    python benchmarks/box_layout.py examples/campaigns/empty_the_box.toml --trials 40 \\
        --only robot=melfa --only engine=mujoco --only task=empty_the_box_vision
"""

from __future__ import annotations

import argparse
import itertools
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from atd.campaign.cells import parse_only, plans  # noqa: E402
from atd.campaign.record import TrialRecord  # noqa: E402
from atd.campaign.spec import load_spec  # noqa: E402
from atd.campaign.trial import trial_run  # noqa: E402
from atd.model.diagnostics import render_all  # noqa: E402

LIMITS = (0.005, 0.01, 0.02)  # m: a wall touched, a fingertip's thickness, a finger's


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("spec", type=Path)
    parser.add_argument("--trials", type=int, default=20)
    parser.add_argument("--only", action="append", default=[], help="DIMENSION=VALUE, as atd campaign run's")
    args = parser.parse_args()
    loaded, found = load_spec(args.spec)
    if loaded is None:
        sys.exit(render_all(found))
    rows = []
    for plan in itertools.islice(plans(loaded, parse_only(tuple(args.only)), args.trials), args.trials):
        run, _ = trial_run(plan, TrialRecord(cell=plan.cell, index=plan.index, seed=plan.seed))
        robot = run.robot
        box = robot.scene.container(plan.world.into)
        poses = robot.object_poses()
        gaps = [(body.name, box.gap_to_walls(body, poses[body.name])) for body in robot.scene.objects]
        robot.close()
        print(f"trial {plan.index}: " + ", ".join(f"{name} {100 * gap:.1f} cm" for name, gap in gaps), flush=True)
        rows.append([gap for _, gap in gaps])
    gaps = np.array(rows)
    for limit in LIMITS:
        print(f"under {100 * limit:.1f} cm from a wall: {(gaps < limit).mean():.0%} of {gaps.size} objects; "
              f"trials with one or more: {(gaps < limit).any(axis=1).mean():.0%} of {len(gaps)}")
    print(f"median gap {100 * float(np.median(gaps)):.1f} cm")


if __name__ == "__main__":
    main()
