"""Perturbations: what is true differs from what the robot believes.

The ATD is the robot's belief and the factory is told nothing else. A perturbation model
draws values from a trial's own generator and changes only the truth: the world the
simulator builds (object pose, mass, friction), the robot the simulator builds (its hand's
mass and servos, its sensors), or the approach the robot takes to its grasp (thesis 3.4.1:
the approach vector off by up to 5 cm and 15° per axis). Every drawn value is returned by
name, to be stored with the trial. The controllers' model of their robot is the factory's
(`Factory.info`), so a perturbed robot never reaches them.

Each model is its own type with its own parameters, so a spec that gives a model another
model's parameter is refused; `MODELS` names them all.

Signs: each component is drawn uniformly from [-m, +m] for a magnitude m, so the seeds'
U(0, 5) cm and U(0, 15)° are the sizes of the errors and either direction is equally likely.
"""

from __future__ import annotations

import math
import typing
from dataclasses import dataclass, replace
from typing import Annotated, Callable, Literal, Sequence, Union

import numpy as np
from pydantic import Field

from atd.campaign.fields import Count, Number, PositiveScales, Scales, StrictTable, within
from atd.model import ranges
from atd.model.controllers import ParamValue
from atd.model.estd import Estd, EstdState
from atd.model.frames import rotation_angle, rotation_rpy
from atd.model.vocabulary import StateType
from atd.sim.scene import Scene
from factories.description import Link, RobotDescription, SensorModel, Servo

APPROACH_MOVES = ("cartesian_move",)  # arm controllers that bring the hand to a grasp
#: A model's keys that say which cells it makes, not how it perturbs a trial.
CELL_KEYS = ("objects", "trials")

# The ranges of the models' own numbers (their scale ranges are in atd.model.ranges).
SHIFT = ranges.Range(0.0, 0.2, "m")  # an approach or object-pose error per axis: a hand's width
TILT = ranges.Range(0.0, 90.0, "deg")  # an approach error about each axis
TURN = ranges.Range(0.0, 180.0, "deg")  # an object turned about z: either way round


@dataclass(frozen=True)
class Truth:
    """What a trial really runs: the ESTD the robot executes (its plan, but for an approach
    that goes astray), the world the simulator builds, and the robot it builds."""

    estd: Estd
    scene: Scene
    robot: RobotDescription


class PerturbationModel(StrictTable):
    """A model with its parameters: `draw` the values a trial's truth differs by, `apply`
    them to the truth. The base changes nothing. Every model may also say which cells it
    makes (`CELL_KEYS`): only some of the spec's objects, and its own trials per cell (thesis
    Table 3.5 adds noise on one object of Table 3.4's eight, 15 runs each)."""

    objects: tuple[str, ...] = Field((), description="the spec's objects it is tried on (none: all)")
    trials: Count | None = Field(None, ge=ranges.TRIALS.low, le=ranges.TRIALS.high,
                                 description="trials per cell (none: the spec's)")

    def draw(self, rng: np.random.Generator) -> dict[str, float]:
        """Every value this trial's truth differs by, named (metres, degrees, scale factors)."""
        return {}

    def apply(self, truth: Truth, values: dict[str, float]) -> Truth:
        """The truth with the drawn `values` in it."""
        return truth


class NoPerturbation(PerturbationModel):
    """What the ATD says is true."""

    model: Literal["none"]


class ApproachError(PerturbationModel):
    """The hand arrives at the grasp off by a rigid error (thesis 3.4.1)."""

    model: Literal["approach"]
    translation: Annotated[Number, within(SHIFT)] = Field(0.05, description="± m per axis")
    rotation: Annotated[Number, within(TILT)] = Field(15.0, description="± degrees about each axis")

    def draw(self, rng: np.random.Generator) -> dict[str, float]:
        t, r = self.translation, self.rotation
        dx, dy, dz = (float(v) for v in rng.uniform(-t, t, 3))
        roll, pitch, yaw = (float(v) for v in rng.uniform(-r, r, 3))
        return {"dx": dx, "dy": dy, "dz": dz, "roll": roll, "pitch": pitch, "yaw": yaw,
                "translation": math.sqrt(dx * dx + dy * dy + dz * dz),
                "rotation": rotation_angle(rotation_rpy(np.radians((roll, pitch, yaw))))}

    def apply(self, truth: Truth, values: dict[str, float]) -> Truth:
        return replace(truth, estd=approach_taken(truth.estd, values))


class ObjectPose(PerturbationModel):
    """The object stands elsewhere on the table than the ATD says."""

    model: Literal["object_pose"]
    x: Annotated[Number, within(SHIFT)] = Field(0.03, description="± m along x")
    y: Annotated[Number, within(SHIFT)] = Field(0.03, description="± m along y")
    yaw: Annotated[Number, within(TURN)] = Field(20.0, description="± degrees about z")

    def draw(self, rng: np.random.Generator) -> dict[str, float]:
        return {"dx": float(rng.uniform(-self.x, self.x)), "dy": float(rng.uniform(-self.y, self.y)),
                "yaw": float(rng.uniform(-self.yaw, self.yaw))}

    def apply(self, truth: Truth, values: dict[str, float]) -> Truth:
        body = truth.scene.object
        if body is None:
            return truth
        turn = np.eye(4)
        turn[:3, :3] = rotation_rpy((0.0, 0.0, math.radians(values["yaw"])))
        pose = turn @ body.pose
        pose[:3, 3] = body.pose[:3, 3] + (values["dx"], values["dy"], 0.0)
        return replace(truth, scene=replace(truth.scene, object=replace(body, pose=pose)))


class ObjectPhysics(PerturbationModel):
    """The object's mass and friction are scaled."""

    model: Literal["object_physics"]
    mass: PositiveScales = Field((0.5, 2.0), description="mass scale range")
    friction: Scales = Field((0.5, 1.5), description="friction scale range")

    def draw(self, rng: np.random.Generator) -> dict[str, float]:
        return {"mass_scale": float(rng.uniform(*self.mass)), "friction_scale": float(rng.uniform(*self.friction))}

    def apply(self, truth: Truth, values: dict[str, float]) -> Truth:
        body = truth.scene.object
        if body is None:
            return truth
        body = replace(body, mass=body.mass * values["mass_scale"], friction=body.friction * values["friction_scale"])
        return replace(truth, scene=replace(truth.scene, object=body))


class SensorError(PerturbationModel):
    """Each sensor's noise and bias are scaled (an ideal sensor stays ideal)."""

    model: Literal["sensors"]
    noise: Scales = Field((1.0, 3.0), description="noise scale range")
    bias: Scales = Field((0.0, 2.0), description="bias scale range")

    def draw(self, rng: np.random.Generator) -> dict[str, float]:
        return {"noise_scale": float(rng.uniform(*self.noise)), "bias_scale": float(rng.uniform(*self.bias))}

    def apply(self, truth: Truth, values: dict[str, float]) -> Truth:
        scaled = {name: _scaled(sensor, values["noise_scale"], values["bias_scale"])
                  for name, sensor in truth.robot.sensors.items()}
        return replace(truth, robot=replace(truth.robot, sensors=scaled))


class HandPhysics(PerturbationModel):
    """The hand is not as its description says: every hand link's mass (and inertia) is
    scaled, as cables and adapters make a real hand heavier than its datasheet, and so are
    the gains of its finger servos. The wrist sensor weighs the true hand; the controllers'
    gravity compensation and grip-force estimates use the described one."""

    model: Literal["hand_physics"]
    mass: PositiveScales = Field((0.8, 1.25), description="hand mass scale range")
    servo: PositiveScales = Field((0.8, 1.25), description="finger servo gain (stiffness and damping) scale range")

    def draw(self, rng: np.random.Generator) -> dict[str, float]:
        return {"hand_mass_scale": float(rng.uniform(*self.mass)), "servo_scale": float(rng.uniform(*self.servo))}

    def apply(self, truth: Truth, values: dict[str, float]) -> Truth:
        robot = truth.robot
        hand = set(robot.hand_links)
        links = tuple(_scaled_link(link, values["hand_mass_scale"], values["servo_scale"]) if link.name in hand else link
                      for link in robot.links)
        return replace(truth, robot=replace(robot, links=links))


class CapApproach(PerturbationModel):
    """The hand arrives over the cap off where the robot believes it: thesis Table 3.5 adds
    uniform noise of up to 1.5 cm to "the approach vectors calculated to grasp the cap" (from
    the cap's centre as vision estimated it), so every move that brings the hand from the start
    to the first unscrew is shifted by one error, drawn per axis; the jar stays where it is.
    `across` is the error across the approach (x and y, where the reactive alignment can
    correct it), `along` the error along it (z, off by default: the thesis's pinch height
    comes from a guarded descent)."""

    model: Literal["cap_approach"]
    across: Annotated[Number, within(SHIFT)] = Field(0.015, description="± m along x and along y")
    along: Annotated[Number, within(SHIFT)] = Field(0.0, description="± m along z")

    def draw(self, rng: np.random.Generator) -> dict[str, float]:
        dx, dy = (float(v) for v in rng.uniform(-self.across, self.across, 2))
        dz = float(rng.uniform(-self.along, self.along))
        return {"cap_dx": dx, "cap_dy": dy, "cap_dz": dz, "cap_offset": math.sqrt(dx * dx + dy * dy + dz * dz)}

    def apply(self, truth: Truth, values: dict[str, float]) -> Truth:
        shift = np.array((values["cap_dx"], values["cap_dy"], values["cap_dz"]))

        def err(point) -> tuple[float, ...]:
            return tuple(float(v) for v in np.asarray(point, float) + shift)

        return replace(truth, estd=moves_changed(truth.estd, approach_states(truth.estd, StateType.UNSCREW), err))


def _model_name(model: type[PerturbationModel]) -> str:
    return typing.get_args(model.model_fields["model"].annotation)[0]


MODELS: dict[str, type[PerturbationModel]] = {
    _model_name(m): m for m in (NoPerturbation, ApproachError, ObjectPose, ObjectPhysics, SensorError, HandPhysics,
                                 CapApproach)}
"""Every perturbation model by the name a spec gives it as `model`."""

Perturbation = Annotated[Union[tuple(MODELS.values())], Field(discriminator="model")]
"""A spec's perturbation table, read as the model its `model` names."""


def approach_taken(estd: Estd, values: dict[str, float]) -> Estd:
    """The ESTD with the approach error in it: every move that brings the hand to the first
    grasp is moved and turned by the error, about the point the robot believes it grasps
    (the object's centre), so the hand arrives off by exactly the drawn error."""
    if estd.object is None or estd.object.pose is None:
        return estd
    centre = np.array(estd.object.pose.as_array()[:3, 3])
    turn = rotation_rpy(np.radians((values["roll"], values["pitch"], values["yaw"])))
    shift = np.array((values["dx"], values["dy"], values["dz"]))

    def err(point) -> tuple[float, ...]:
        return tuple(float(v) for v in centre + turn @ (np.asarray(point, float) - centre) + shift)

    return moves_changed(estd, approach_states(estd), err, tilt=(values["roll"], values["pitch"], values["yaw"]))


def moves_changed(estd: Estd, moved: set[str], err: Callable[[Sequence[float]], tuple[float, ...]],
                  **extra: ParamValue) -> Estd:
    """The ESTD with the `moved` states' targets and waypoints taken through `err`, and `extra`
    parameters given to their arm controllers."""
    states = []
    for state in estd.states:
        if state.name in moved:
            params = dict(state.arm.params)
            params["target"] = err(params["target"])
            params["waypoints"] = tuple(err(w) for w in params.get("waypoints", ()))
            params.update(extra)
            state = state.model_copy(update={"arm": state.arm.model_copy(update={"params": params})})
        states.append(state)
    return estd.model_copy(update={"states": tuple(states)})


def approach_states(estd: Estd, until: StateType = StateType.GRASP) -> set[str]:
    """The moves the robot makes from the start until it first grasps (or `until`): the
    states reachable from the initial state without passing one, whose arm moves the hand."""
    by_name = {s.name: s for s in estd.states}
    seen, frontier = set(), [estd.initial]
    while frontier:
        name = frontier.pop()
        if name in seen:
            continue
        seen.add(name)
        if by_name[name].type is until:
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


def _scaled_link(link: Link, mass: float, servo: float) -> Link:
    """A hand link `mass` times as heavy (its inertia with it), its joint's servo gains `servo` times."""
    joint = link.joint and replace(link.joint, servo=Servo(link.joint.servo.kp * servo, link.joint.servo.kv * servo))
    inertia = link.inertia and tuple(v * mass for v in link.inertia)
    return replace(link, mass=link.mass * mass, inertia=inertia,
                   inertia_products=tuple(v * mass for v in link.inertia_products), joint=joint)
