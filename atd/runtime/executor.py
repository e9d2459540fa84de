"""The executor: runs an ESTD as a hybrid automaton on a robot (D5 2.2.4).

Each control tick: read every sensor once; check the current state's transitions (in
document order, the first whose events all hold is taken); run the state's arm and hand
controllers; merge their outputs in the arbitrator; send one command; step the robot.
A sub-task state runs its own machine inside it. A watchdog ends any run that outlives
its time budget, so nothing hangs.

A task that names roles may run states on another arm of the robot than the ESTD's own:
one state runs at a time, on its arm, and every arm without a state holds its last
command, its joints still and its hand as last commanded (a grasp keeps its grip while
the other arm works; docs/runtime.md, *Two arms*).
"""

from __future__ import annotations

import time as wallclock
from dataclasses import dataclass, field, replace
from typing import Callable, Mapping

import numpy as np

from atd.model.estd import Condition as Leaf
from atd.model.estd import ConditionGroup, Estd, EstdEvent, EstdState, EstdTransition
from atd.model.vocabulary import StateType
from atd.runtime.arbitrator import RobotCommand, arbitrate
from atd.runtime.trace import Trace
from atd.runtime.values import ArmMemory, arm_for, bind_inputs, targeted, topped
from primitives.base import Condition, Context, ControlData, Status, StateView
from primitives.blackboard import ARM_TWIST, Blackboard
from primitives.registry import BuildError, build_condition, build_controller
from primitives.robot import Readings, Robot, RobotInfo


class SharedLeaf:
    """A leaf condition as a state's events share it: the same leaf (kind, sensors and
    parameters) in several events of a state, as a translation's `success` and
    `grasp_stable` both ask for a stable grasp, is one condition, asked once a tick. Two
    copies would see the same readings and keep the same timers: the same verdicts, at twice
    the cost."""

    def __init__(self, condition: Condition) -> None:
        self.condition = condition
        self.verdict = False  # this tick's


def _leaf_key(leaf: Leaf) -> tuple:
    return leaf.kind, tuple(leaf.sensors), repr(sorted(leaf.params.items()))


class ConditionTree:
    """An event's `all`/`any` tree of leaf conditions. Leaves already in `shared` (by kind,
    sensors and parameters) are those; new ones are added to it. The state asks every
    leaf of `shared` once a tick, so that every debounce timer sees every tick; the tree
    then only combines their verdicts."""

    def __init__(self, node: Leaf | ConditionGroup, ctx: Context, shared: dict[tuple, SharedLeaf] | None = None) -> None:
        self.node = node
        shared = {} if shared is None else shared
        if isinstance(node, Leaf):
            key = _leaf_key(node)
            if key not in shared:
                shared[key] = SharedLeaf(build_condition(node, ctx))
            self.leaf: SharedLeaf | None = shared[key]
            self.children: list[ConditionTree] = []
        else:
            self.leaf = None
            self.children = [ConditionTree(child, ctx, shared) for child in node.children]
        self.every = isinstance(node, ConditionGroup) and node.op == "all"

    def holds(self) -> bool:
        """The tree's verdict on this tick's leaf verdicts."""
        if self.leaf:
            return self.leaf.verdict
        if self.every:
            for child in self.children:
                if not child.holds():
                    return False
            return True
        for child in self.children:
            if child.holds():
                return True
        return False

    def evidence(self) -> list[dict]:
        """The leaves behind a verdict, with the readings each recorded."""
        if self.leaf:
            return [{"kind": self.node.kind, "atd": self.node.atd, "sensors": list(self.node.sensors),
                     **self.leaf.condition.evidence}]
        return [item for child in self.children for item in child.evidence()]


@dataclass(frozen=True)
class OtherArm:
    """An arm of the robot besides the ESTD's own: the context its controllers are built with
    and its robot interface, read when one of its states runs."""

    context: Context
    robot: Robot


Output = tuple[str | None, ControlData]  # the arm a controller drives (None: the ESTD's own) and its output


@dataclass
class Edge:
    transition: EstdTransition
    events: list[tuple[EstdEvent, ConditionTree]]


@dataclass
class Visit:
    """One stay in a state, for the run's summary."""

    path: str
    atd: str
    entered: float
    left: float | None = None
    left_by: str | None = None  # ATD id of the transition taken
    left_on: list[str] = field(default_factory=list)  # the abstract events of that transition


class Machine:
    """One (sub-)machine being run: its current state and what runs in it."""

    def __init__(self, estd: Estd, prefix: str, base: Context, trace: Trace, visits: list[Visit],
                 others: Mapping[str, OtherArm] | None = None) -> None:
        self.estd = estd
        self.others = others or {}
        self.prefix = prefix
        self.base = base
        self.trace = trace
        self.visits = visits
        self.states = estd.states_by_name
        self.ended: EstdState | None = None
        self.current: EstdState | None = None
        self.last_exit: Visit | None = None  # the visit left by the latest transition

    # -- entering a state ---------------------------------------------------------------
    def enter(self, name: str, readings: Readings) -> None:
        """Enter state `name`; `readings` are the ESTD's own arm's (a state on another arm
        reads its own)."""
        state = self.states[name]
        self.current = state
        self.on = self.others.get(state.robot_arm) if state.robot_arm else None
        self.driven = state.robot_arm if self.on else None
        base = self.on.context if self.on else self.base
        outer, readings = readings, self._mine(readings)
        self.entered = readings.time
        ctx = replace(base, blackboard=Blackboard())
        arm = topped(arm_for(state, base.memory), state, base.memory)
        self.arm = build_controller(arm, "arm", ctx) if arm else None
        self.hand = build_controller(state.hand, "hand", ctx) if state.hand else None
        leaves: dict[tuple, SharedLeaf] = {}
        self.edges = [
            Edge(t, [(e, ConditionTree(e.condition, ctx, leaves)) for e in t.events])
            for t in self.estd.leaving.get(name, ())
        ]
        self.visit = Visit(self.prefix + name, state.atd, readings.time)
        self.visits.append(self.visit)
        self.trace.write("enter", readings.time, state=self.visit.path, atd=state.atd, primitive=state.primitive)
        for controller in (self.arm, self.hand):
            if controller:
                controller.start(readings)
        self.leaves = list(leaves.values())  # in the order the edges first name them
        for leaf in self.leaves:
            leaf.condition.start(readings)
        self.sub = Machine(state.machine, f"{self.visit.path}/", self.base, self.trace, self.visits, self.others) \
            if state.machine is not None else None
        if self.sub:
            bind_inputs(state, self.base.memory)
            self.sub.enter(state.machine.initial, outer)
        if state.type.is_end:
            self.ended = state
            self.trace.write("end", readings.time, state=self.visit.path, atd=state.atd, outcome=state.type.value)

    # -- one tick -------------------------------------------------------------------------
    def _mine(self, readings: Readings) -> Readings:
        """The readings of the current state's arm, given the ESTD's own arm's."""
        return self.on.robot.read() if self.on else readings

    def _view(self, readings: Readings) -> StateView:
        sub = end = None
        if self.sub and self.sub.ended:
            sub = Status.DONE if self.sub.ended.type is StateType.SUCCESS else Status.ERROR
            end = self.sub.ended.name
        return StateView(
            elapsed=readings.time - self.entered,
            arm=self.arm.status if self.arm else Status.DONE,
            hand=self.hand.status if self.hand else Status.DONE,
            subtask=sub,
            subtask_end=end,
            reasons={k: c.reason for k, c in (("arm", self.arm), ("hand", self.hand)) if c and c.reason},
            counts={k: c.counts for k, c in (("arm", self.arm), ("hand", self.hand)) if c and c.counts},
        )

    def _fired(self, readings: Readings, dt: float) -> Edge | None:
        """The first edge whose events all hold; every leaf is asked first, whatever the
        edges make of it, so that every timer counts on."""
        view = self._view(readings)
        for leaf in self.leaves:
            leaf.verdict = leaf.condition.holds(readings, view, dt)
        for edge in self.edges:
            for _, tree in edge.events:
                if not tree.holds():
                    break
            else:
                return edge
        return None

    def tick(self, readings: Readings, dt: float) -> list[Output]:
        """Take a transition if one fires, then return the current state's control outputs,
        each with the arm it drives; `readings` are the ESTD's own arm's."""
        if self.ended:
            return []
        if self.sub and not self.sub.ended:
            outputs = self.sub.tick(readings, dt)
        else:
            outputs = []
        mine = self._mine(readings)
        edge = self._fired(mine, dt)
        if edge is not None:
            self._take(edge, readings)
            if self.ended:
                return []
            outputs = self.sub.tick(readings, dt) if self.sub else []
            mine = self._mine(readings)  # the new state's arm
        for controller in (self.arm, self.hand):
            if controller:
                outputs.append((self.driven, controller.update(mine, dt)))
        return outputs

    def _take(self, edge: Edge, readings: Readings) -> None:
        t = edge.transition
        for event, tree in edge.events:
            self.trace.write("event", readings.time, state=self.visit.path, event=event.type.value, atd=event.atd,
                             transition=t.atd, conditions=tree.evidence())
        self.visit.left, self.visit.left_by = readings.time, t.atd
        self.visit.left_on = [e.type.value for e in t.events]
        self.last_exit = self.visit
        self.trace.write("exit", readings.time, state=self.visit.path, atd=self.current.atd, transition=t.atd,
                         destination=t.destination, duration=readings.time - self.entered)
        self.enter(t.destination, readings)

    def innermost(self) -> Machine:
        return self.sub.innermost() if self.sub and not self.sub.ended else self


@dataclass
class Outcome:
    """How a run ended, in the ATD's terms; `wall_clock_stopped`: the watchdog's wall-clock
    limit ended it (how fast the machine ran it, not what the robot did)."""

    succeeded: bool
    summary: str
    end_state: str | None
    visits: list[Visit]
    sim_time: float
    wall_time: float
    ticks: int
    wall_clock_stopped: bool = False

    @property
    def real_time_factor(self) -> float:
        return self.sim_time / self.wall_time if self.wall_time > 0 else float("inf")


Progress = Callable[[str, float, float], None]  # (current state path, sim time, wall time)
Observer = Callable[[float], None]  # called after every control step with the simulated time


def build_problems(estd: Estd, base: Context, others: Mapping[str, Context] | None = None) -> list[str]:
    """Everything in the ESTD this robot cannot build (a controller its hand does not have,
    a sensor it lacks), found before the run starts rather than in the middle of it; a state
    on another arm is built with that arm's context (`others`, by arm name)."""
    problems = []
    contexts = {name: replace(c, blackboard=Blackboard()) for name, c in (others or {}).items()}
    for prefix, machine in estd.walk():
        own = replace(base, blackboard=Blackboard())
        for state in machine.states:
            ctx = contexts.get(state.robot_arm or "", own)
            # A target read at run time could be anywhere: any point shows the controller builds.
            anywhere = {"target": (0.0, 0.0, 0.0), "yaw": 0.0}
            arm = targeted(state.arm, anywhere) if state.arm and state.target_from else state.arm
            for role, use in (("arm", arm), ("hand", state.hand)):
                if use is not None:
                    try:
                        build_controller(use, role, ctx)
                    except BuildError as exc:
                        problems.append(f"state '{prefix}{state.name}': {exc}")
        for transition in machine.transitions:
            origin = machine.states_by_name.get(transition.origin)
            ctx = contexts.get(origin.robot_arm or "", own) if origin else own
            for event in transition.events:
                try:
                    ConditionTree(event.condition, ctx)
                except BuildError as exc:
                    problems.append(f"transition '{prefix}{transition.atd}' event '{event.type.value}': {exc}")
    return problems


WALL_BUDGET = 600.0  # s of wall-clock time before the watchdog stops a run (a hang, or a machine far too slow)


class Executor:
    """Runs one ESTD on one robot until an end state, or the watchdog, stops it."""

    def __init__(self, estd: Estd, robot: Robot, base: Context, trace: Trace | None = None,
                 budget: float = 300.0, wall_budget: float = WALL_BUDGET,
                 others: Mapping[str, tuple[Robot, RobotInfo]] | None = None) -> None:
        """`others`: the robot's other arms by name, for a task that names roles, each with what
        its controllers know of it (its factory's description); they share `robot`'s world, and
        `robot.step()` moves them all."""
        self.estd = estd
        self.robot = robot
        self.trace = trace or Trace()
        self.visits: list[Visit] = []
        arms: dict[str, OtherArm] = {}
        if others:  # each arm learns of itself on its own; named values are the run's
            shared = base.memory
            base = replace(base, memory=ArmMemory(shared))
            arms = {name: OtherArm(replace(base, info=info, camera=r.capture, memory=ArmMemory(shared)), r)
                    for name, (r, info) in others.items()}
        self.machine = Machine(estd, "", base, self.trace, self.visits, arms)
        self.budget = budget
        self.wall_budget = wall_budget
        self._arms: dict[str | None, tuple[Robot, Context]] = {None: (robot, base)}
        self._arms |= {name: (arm.robot, arm.context) for name, arm in arms.items()}
        # Per arm: its hand's DOF count, and its command when no controller moves it.
        self._idle = {name: (len(r.info.hand.dofs), np.zeros(r.info.arm_dof)) for name, (r, _) in self._arms.items()}
        self.command: RobotCommand | None = None  # the arbitrator's latest, for recordings
        self.stopped: str | None = None  # why an observer stopped the run (`stop`)

    def stop(self, why: str) -> None:
        """End the run before its next tick, as a supervisor would (a campaign's judge that
        sees the work done by a task that cannot know it is)."""
        self.stopped = why

    def _apply(self, outputs: list[Output]) -> None:
        """One command per arm: its controllers' outputs merged, or none, and it holds."""
        for name, (robot, ctx) in self._arms.items():
            hand_dof, still = self._idle[name]
            command = arbitrate([out for on, out in outputs if on == name], hand_dof)
            if name is None:
                self.command = command
            dq = command.joint_velocity
            if command.twist is not None and np.count_nonzero(command.twist):  # a third of .any()'s cost, every tick
                twisted = robot.twist_velocities(command.twist)
                dq = twisted if dq is None else dq + twisted
            elif dq is None:
                dq = still
            ctx.memory[ARM_TWIST] = command.twist
            robot.command_arm_velocity(dq)
            if command.hand_values is not None:
                robot.command_hand(command.hand_values, command.hand_modes)

    def run(self, progress: Progress | None = None, every: int = 200,
            observers: tuple[Observer, ...] = ()) -> Outcome:
        started = wallclock.perf_counter()
        dt = self.robot.info.control_period
        readings = self.robot.read()
        self.machine.enter(self.estd.initial, readings)
        ticks = 0
        shown = ""
        verdict: str | None = None
        wall_clock_stopped = False
        others = [other for other, _ in list(self._arms.values())[1:]]
        while not self.machine.ended:
            readings = self.robot.read()
            for other in others:
                other.read()  # every arm's sensors sampled each tick, as the ESTD's own
            wall = wallclock.perf_counter() - started
            if readings.time >= self.budget or wall >= self.wall_budget:
                wall_clock_stopped = readings.time < self.budget
                verdict = self._watchdog(readings, wall_clock_stopped)
                break
            if self.stopped:
                verdict = f"stopped in '{self.machine.innermost().visit.path}': {self.stopped}"
                self.trace.write("stopped", readings.time, state=self.machine.innermost().visit.path, why=self.stopped)
                break
            self._apply(self.machine.tick(readings, dt))
            if self.machine.ended:
                break
            self.robot.step()
            ticks += 1
            for observe in observers:
                observe(readings.time + dt)
            if progress:
                where = self.machine.innermost().visit.path
                if where != shown or ticks % every == 0:
                    shown = where
                    progress(where, readings.time, wall)
        wall = wallclock.perf_counter() - started
        end = self.machine.ended
        return Outcome(
            succeeded=end is not None and end.type is StateType.SUCCESS,
            summary=verdict or self._summary(),
            end_state=end.name if end else None,
            visits=self.visits,
            sim_time=readings.time,
            wall_time=wall,
            ticks=ticks,
            wall_clock_stopped=wall_clock_stopped,
        )

    def _watchdog(self, readings: Readings, wall_clock: bool) -> str:
        where = self.machine.innermost().visit
        limit = f"{self.wall_budget:g} s of wall-clock time" if wall_clock else f"{self.budget:g} s of simulated time"
        self.trace.write("watchdog", readings.time, state=where.path, atd=where.atd, limit=limit)
        return f"failed: the watchdog stopped the run in '{where.path}' after {limit}"

    def _summary(self) -> str:
        end, last = self.machine.ended, self.machine.last_exit
        if end.type is StateType.SUCCESS:
            return f"succeeded: reached '{end.name}'"
        if last is None:
            return f"failed: started in failure state '{end.name}'"
        return (f"failed in '{last.path}' on {' and '.join(last.left_on)}, "
                f"abstract edge {last.left_by.replace('->', ' -> ')}")
