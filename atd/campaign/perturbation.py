"""Perturbations: what is true differs from what the robot believes.

The ATD is the robot's belief and the factory is told nothing else. A perturbation
samples values from a trial's own generator and changes only the truth: the world the
simulator builds (object pose, mass, friction), the robot's sensors, or the approach the
robot takes to its grasp (thesis 3.4.1: the approach vector off by up to 5 cm and 15°
per axis). Every sampled value is returned by name, to be stored with the trial.

Signs: each component is drawn uniformly from [-m, +m] for a magnitude m, so the seeds'
U(0, 5) cm and U(0, 15)° are the sizes of the errors and either direction is equally likely.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from atd.model.estd import Estd, EstdState
from atd.sim.scene import Scene
from atd.model.frames import rotation_angle, rotation_rpy
from factories.description import RobotDescription, SensorModel

if TYPE_CHECKING:
    from atd.campaign.spec import Perturbation

PERTURBATIONS = ("none", "approach", "object_pose", "object_physics", "sensors")
APPROACH_MOVES = ("cartesian_move",)  # arm controllers that bring the hand to a grasp


def sample(model: Perturbation, rng: np.random.Generator) -> dict[str, float]:
    """Every value this trial's truth differs by, named (metres, degrees, scale factors)."""
    if model.model == "approach":
        t, r = model.translation, model.rotation
        dx, dy, dz = (float(v) for v in rng.uniform(-t, t, 3))
        roll, pitch, yaw = (float(v) for v in rng.uniform(-r, r, 3))
        return {"dx": dx, "dy": dy, "dz": dz, "roll": roll, "pitch": pitch, "yaw": yaw,
                "translation": math.sqrt(dx * dx + dy * dy + dz * dz),
                "rotation": rotation_angle(rotation_rpy(np.radians((roll, pitch, yaw))))}
    if model.model == "object_pose":
        return {"dx": float(rng.uniform(-model.x, model.x)), "dy": float(rng.uniform(-model.y, model.y)),
                "yaw": float(rng.uniform(-model.yaw, model.yaw))}
    if model.model == "object_physics":
        return {"mass_scale": float(rng.uniform(*model.mass)), "friction_scale": float(rng.uniform(*model.friction))}
    if model.model == "sensors":
        return {"noise_scale": float(rng.uniform(*model.noise)), "bias_scale": float(rng.uniform(*model.bias))}
    return {}


def true_scene(scene: Scene, model: str, values: dict[str, float]) -> Scene:
    """The world as it really is, from the world the robot believes in."""
    body = scene.object
    if body is None:
        return scene
    if model == "object_pose":
        turn = np.eye(4)
        turn[:3, :3] = rotation_rpy((0.0, 0.0, math.radians(values["yaw"])))
        pose = turn @ body.pose
        pose[:3, 3] = body.pose[:3, 3] + (values["dx"], values["dy"], 0.0)
        return replace(scene, object=replace(body, pose=pose))
    if model == "object_physics":
        return replace(scene, object=replace(body, mass=body.mass * values["mass_scale"],
                                             friction=body.friction * values["friction_scale"]))
    return scene


def true_robot(robot: RobotDescription, model: str, values: dict[str, float]) -> RobotDescription:
    """The robot with its real sensors: noise and bias scaled (an ideal sensor stays ideal)."""
    if model != "sensors":
        return robot
    scaled = {name: _scaled(sensor, values["noise_scale"], values["bias_scale"])
              for name, sensor in robot.sensors.items()}
    return replace(robot, sensors=scaled)


def approach_taken(estd: Estd, model: str, values: dict[str, float]) -> Estd:
    """The ESTD with the approach error in it: every move that brings the hand to the first
    grasp is moved and turned by the error, about the point the robot believes it grasps
    (the object's centre), so the hand arrives off by exactly the sampled error."""
    if model != "approach" or estd.object is None or estd.object.pose is None:
        return estd
    centre = np.array(estd.object.pose.as_array()[:3, 3])
    turn = rotation_rpy(np.radians((values["roll"], values["pitch"], values["yaw"])))
    shift = np.array((values["dx"], values["dy"], values["dz"]))
    moved = approach_states(estd)

    def err(point) -> tuple[float, ...]:
        return tuple(float(v) for v in centre + turn @ (np.asarray(point, float) - centre) + shift)

    states = []
    for state in estd.states:
        if state.name in moved:
            params = dict(state.arm.params)
            params["target"] = err(params["target"])
            params["waypoints"] = tuple(err(w) for w in params.get("waypoints", ()))
            params["tilt"] = (values["roll"], values["pitch"], values["yaw"])
            state = state.model_copy(update={"arm": state.arm.model_copy(update={"params": params})})
        states.append(state)
    return estd.model_copy(update={"states": tuple(states)})


def approach_states(estd: Estd) -> set[str]:
    """The moves the robot makes from the start until it first grasps: the states
    reachable from the initial state without passing a grasp, whose arm moves the hand."""
    by_name = {s.name: s for s in estd.states}
    seen, frontier = set(), [estd.initial]
    while frontier:
        name = frontier.pop()
        if name in seen:
            continue
        seen.add(name)
        if by_name[name].type.value == "grasp":
            continue
        frontier += [t.destination for t in estd.transitions if t.origin == name]
    return {n for n in seen if _moves_hand(by_name[n])}


def _moves_hand(state: EstdState) -> bool:
    return (state.type.value == "move" and state.arm is not None and state.arm.name in APPROACH_MOVES
            and "target" in state.arm.params)


def _scaled(sensor: SensorModel, noise: float, bias: float) -> SensorModel:
    def times(value, k):
        return tuple(v * k for v in value) if isinstance(value, tuple) else value * k

    return replace(sensor, noise_std=times(sensor.noise_std, noise), bias=times(sensor.bias, bias))

