"""The `perceive` arm controller: one of thesis 3.4.3's approach-vector generators, chosen by
its `method` parameter, run as a state of the task."""

from __future__ import annotations

import math
from typing import Callable, Mapping

from primitives.base import Context, Status
from primitives.blackboard import AIMED
from primitives.perception.blind import BlindExploration
from primitives.perception.generators import VisionSettings, random_blind, vision
from primitives.perception.perceiver import Perceiver
from primitives.robot import Readings


class RandomBlind(Perceiver):
    """Random blind: an approach drawn over the container's whole floor, from the run's seeded
    generator, the hand moved in and turned where the walls leave it no room (`grasp_extent`).
    It always finds "something"."""

    method = "random_blind"

    def start(self, readings: Readings) -> None:
        super().start(readings)
        extent = self.params["grasp_extent"]
        self.found(random_blind(self.container, self.ctx.rng, (float(extent[0]), float(extent[1])),
                                self.approaching), "")


class Vision(Perceiver):
    """Vision: one picture of the depth camera `camera` (the robot's first when empty), its
    points inside the container clustered, one cluster chosen at random among those the run's
    earlier vision rounds aimed at least often (`AIMED`)."""

    method = "vision"

    def __init__(self, ctx: Context) -> None:
        super().__init__(ctx)
        p = self.params
        cameras = ctx.info.cameras
        self.camera = str(p.get("camera", "")) or (cameras[0] if cameras else "")
        if self.camera not in cameras:
            raise ValueError(f"vision needs a depth camera; the {ctx.info.name} has "
                             f"{'only ' + ', '.join(cameras) if cameras else 'none'}"
                             + (f", not '{self.camera}'" if self.camera else ""))
        extent = p["grasp_extent"]
        band = tuple(float(v) for v in p["jaw_band"])
        footprint = tuple(float(v) for v in p["grasp_footprint"])
        others = tuple(float(v) for v in p["other_tips"])
        self.settings = VisionSettings(float(p["floor_margin"]), float(p["wall_margin"]), float(p["above_rim"]),
                                       float(p["voxel"]), int(p["min_points"]), (float(extent[0]), float(extent[1])),
                                       (band[0], band[1], band[2]),
                                       (footprint[0], footprint[1], footprint[2], footprint[3]),
                                       math.radians(float(p["grasp_turn"])), (others[0], others[1], others[2]))

    def start(self, readings: Readings) -> None:
        super().start(readings)
        if self.ctx.camera is None:
            self.finish(Status.ERROR, "this run gives the controller no camera to take a picture with")
            return
        image = self.ctx.camera(self.camera)
        aimed = self.ctx.memory.get(AIMED, ())
        approach = vision(image, self.container, self.ctx.rng, self.settings, self.approaching, aimed)
        if approach is not None:
            self.ctx.memory[AIMED] = (*aimed, approach.point)
        self.found(approach,
                   f"no cluster of {self.settings.min_points} points or more inside the container in the "
                   f"'{self.camera}' picture")


METHODS: Mapping[str, Callable[[Context], Perceiver]] = {
    "random_blind": RandomBlind,
    "blind_exploration": BlindExploration,
    "vision": Vision,
}


def perceive(ctx: Context) -> Perceiver:
    """The perceive controller of the state's `method`."""
    return METHODS[str(ctx.params["method"])](ctx)
