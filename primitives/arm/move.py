"""Moving the TCP: holding still, and the move/transport controller (thesis 3.3.2, Eq. 3.3).

The same Cartesian controller serves every arm (thesis 7.3) and every ATD movement type
(thesis 7.2): free (any path: straight at the goal, or over the top of known obstacles), guarded
(along the straight Cartesian line, ending on contact), constrained (the hand's
orientation held all along, inside the velocity and acceleration limits).
"""

from __future__ import annotations

import numpy as np

from atd.model.frames import rotation_rpy
from primitives.arm.motion import (
    GAIN,
    ORIENTATION_TOLERANCE,
    STALL_TIME,
    ObstacleDetour,
    Stall,
    TwistShaper,
    clamp_norm,
    norm,
    orientation_twist,
    heading_of,
    roll_room,
    top_down,
    turn_to_yaw,
    what_stops,
)
from primitives.base import ArmCommand, Context, ControlData, Controller, Status
from primitives.blackboard import ARM_TWIST, HAND_LEVEL, SHORT_OF_TARGET, YAW_REFERENCE
from primitives.filters import ContactWrench, Leaving, LowPass
from primitives.robot import Readings

VIA_TOLERANCE = 0.01  # m: a via point counts as passed this close
# N of contact force on a stalled guarded move: what stopped it is a contact, not the arm.
# A position-servoed arm blocked near its target presses with little force (a Melfa jaw
# resting on the object's top: about 2 N), far below any contact threshold.
STALL_CONTACT = 1.0
CRUISE = 0.9  # fraction of max_speed at which a push starts measuring its free-motion level
# m a guarded move that ends on contact rests short of it: held where it stopped, the Barrett
# went on pressing a fingertip on the steel weight's top at 19 N, and the preshape the hand
# made meanwhile dragged its spread round under that load for 6 s instead of 1.5
EASE_OFF = 0.003
# the hand's x axis this far up or down, or its approach axis this far from down: its yaw is the last level hand's
SIDEWAYS = np.sin(np.radians(45.0))


def arm_output(twist: np.ndarray) -> ControlData:
    return ControlData(arm=ArmCommand(twist=twist))


class Hold(Controller):
    """Keep the TCP where it was when the state began (D5 2.2.4: the arm idles while the
    hand works). Done at once. Follows the hand side's `arm_nudge`, so a gripper can
    re-centre itself on the object by moving the arm."""

    def start(self, readings: Readings) -> None:
        self.position = readings.tcp[:3, 3].copy()
        self.rotation = readings.tcp[:3, :3].copy()
        self.finish(Status.DONE, "holding the pose")

    def update(self, readings: Readings, dt: float) -> ControlData:
        nudge = self.ctx.blackboard.arm_nudge
        v = np.zeros(3)
        if nudge is not None:
            v = np.asarray(nudge, float)
            self.position = self.position + v * dt
        v = v + GAIN * (self.position - readings.tcp[:3, 3])
        w, _ = orientation_twist(self.rotation, readings.tcp[:3, :3])
        return arm_output(np.concatenate([v, w]))


class CartesianMove(Controller):
    """Move the TCP through the waypoints to the target; stop on a contact (Eq. 3.3).

    v = n (x_goal - x) while ||F|| < FORCE_THRESHOLD, else 0, with n keeping v within the
    speed limit. On a guarded move the contact is what the motion looks for, so stopping
    on it is success, unless `contact_margin` says how near the target it must come (a
    move carrying an object stopped short of where it goes has met resistance); on any
    other move it is unexpected. Either way the controller gives up (status ERROR),
    leaving the collision event to say what happened. The hand ends
    top-down (hand z = world -z) with the yaw it started with, or given `yaw` that yaw or its
    opposite (`turn_to_yaw`; not `either_way`, that yaw itself), turned by `tilt` where given; or, not `level`, as it started
    (turned about the vertical to `yaw` where given), turned by `tilt`: a transport lifts the object as the
    grasp holds it: the object, standing on the table as the jaws closed, is upright in the
    tilted hand, levelling the hand would tip it, and it can take a wrist into its singularity
    (docs/constants.md).
    """

    def __init__(self, ctx: Context) -> None:
        super().__init__(ctx)
        p = self.params
        self.target = np.asarray(p["target"], float)
        self.hand_point = np.asarray(p["hand_point"], float)
        self.via = [np.asarray(w, float) for w in p.get("waypoints", ())] + [self.target]
        self.straight = bool(p["straight_line"])
        self.keep_orientation = bool(p["keep_orientation"])
        self.threshold = float(p["force_threshold"])
        self.max_speed = float(p["max_speed"])
        self.tolerance = float(p["tolerance"])
        self.tilt = rotation_rpy(np.radians(np.asarray(p["tilt"], float)))
        self.level = bool(p["level"])
        self.yaw = None if p.get("yaw") is None else np.radians(float(p["yaw"]))
        self.either_way = bool(p["either_way"])
        self.wrist_roll = float(p["wrist_roll"])
        self.margin = float(p["contact_margin"])
        # a free move may start off a press (fingers blocked on what they let go): its easing is no contact
        leaving = None if self.straight else Leaving(ctx.info.hand, self.threshold)
        self.contact = ContactWrench(float(p["filter_time"]), leaving)
        self.shaper = TwistShaper(p["velocity_limits"], p["acceleration_limits"])
        self.detour = ObstacleDetour(p.get("obstacles", ()), p.get("obstacle_sizes", ()))
        self.stall = Stall()
        self.rest: np.ndarray | None = None  # where to stay once finished; None = stand still
        self._leg_line: tuple | None = None  # the current leg's ends and what `_leg` works out from them

    def start(self, readings: Readings) -> None:
        self.contact.start(readings)
        self.shaper.start(self.ctx.memory.get(ARM_TWIST))
        self.ctx.memory.pop(SHORT_OF_TARGET, None)
        start = readings.tcp[:3, :3]
        sideways = abs(float(start[2, 0])) > SIDEWAYS or float(start[2, 2]) > -SIDEWAYS
        turned = self.ctx.memory.get(HAND_LEVEL) if sideways else None
        level = top_down(start) if turned is None else turned
        if self.yaw is not None:
            reference = self.ctx.memory.setdefault(YAW_REFERENCE, heading_of(level))
            info = self.ctx.info
            room = roll_room(readings.arm_q, info.arm_lower, info.arm_upper, self.wrist_roll)
            turn = turn_to_yaw(level, self.yaw, reference, self.either_way, room)
            level, start = turn @ level, turn @ start
        self.rotation = self.tilt @ (level if self.level else start)
        self.via[-1] = self.target - self.rotation @ self.hand_point  # the yaw, and so where that point is, known now
        if self.level:
            self.ctx.memory[HAND_LEVEL] = level
        self.leg = 0
        self.leg_start = readings.tcp[:3, 3].copy()
        self.points = []
        for point in self.via:
            self.points += self.detour.route(self.points[-1] if self.points else self.leg_start, point)
        self.stall.reset(readings.time)

    def update(self, readings: Readings, dt: float) -> ControlData:
        if self.status is not Status.RUNNING:
            return self._stay(readings)
        self.contact.update(readings, dt)
        force = self.contact.force
        if force >= self.threshold:
            self.shaper.stop()
            position = readings.tcp[:3, 3]
            self._stopped(force, position)
            if self.status is Status.DONE:  # ease off what it met, or the arm goes on pressing on it
                leg = self.points[self.leg] - self.leg_start
                self.rest = position - EASE_OFF * leg / max(norm(leg), 1e-9)
            return self._stay(readings)

        position = readings.tcp[:3, 3]
        goal = self.points[self.leg]
        distance = norm(goal - position)
        if self.leg < len(self.points) - 1 and distance < VIA_TOLERANCE:
            self.leg_start, self.leg = goal, self.leg + 1
            self.stall.reset(readings.time)
            goal = self.points[self.leg]
            distance = norm(goal - position)

        self.sense(readings, self._leg(goal)[0], dt)
        w, angle = orientation_twist(self.rotation, readings.tcp[:3, :3])
        if self.leg == len(self.points) - 1 and distance < self.tolerance and angle < ORIENTATION_TOLERANCE:
            self.rest = goal
            self.arrived(distance)
            return self._stay(readings)
        if self.stall.stalled(distance, readings.time, angle):
            self.shaper.stop()
            if self.straight and force >= STALL_CONTACT:
                self._stopped(force, position)
                return self._stay(readings)
            info = self.ctx.info
            self.finish(Status.ERROR, f"no progress for {STALL_TIME:g} s, {distance:.3f} m and {np.degrees(angle):.0f} "
                                      f"degrees from ({goal[0]:.3f}, {goal[1]:.3f}, {goal[2]:.3f}): "
                                      f"{what_stops(readings.arm_q, info.arm_joints, info.arm_lower, info.arm_upper)}")
            return self._stay(readings)

        v = self._line(position, goal) if self.straight else clamp_norm(GAIN * (goal - position), self.max_speed)
        if self.keep_orientation and angle > ORIENTATION_TOLERANCE:
            v = v * (ORIENTATION_TOLERANCE / angle)  # turn back first, then move on
        return arm_output(self.shaper(np.concatenate([v, w]), dt))

    def _stopped(self, force: float, position: np.ndarray) -> None:
        """Stopped on a contact at `position`: `stopped_by` says what it was; a guarded move
        done there leaves how far short of its target it stopped (`SHORT_OF_TARGET`)."""
        to_target = self.via[-1] - position
        self.stopped_by(force, norm(to_target))
        if self.status is Status.DONE:
            self.ctx.memory[SHORT_OF_TARGET] = to_target

    def stopped_by(self, force: float, short: float) -> None:
        """A contact `short` of the target: what a guarded move looks for, the surface a
        place was going to (within `contact_margin`), or else something in the way. It is
        felt over the threshold, or pressing on while the arm makes no progress (a jaw on an
        object's top presses only a few newtons against the arm's servo)."""
        felt = f"|F| = {force:.1f} N " + (f">= {self.threshold:g} N" if force >= self.threshold
                                          else f"pressing, no progress for {STALL_TIME:g} s")
        if not self.straight:
            self.finish(Status.ERROR, f"unexpected contact: {felt}")
        elif 0.0 <= self.margin < short:
            self.finish(Status.ERROR, f"stopped short: contact {short * 100:.1f} cm before the target, {felt}")
        else:
            self.finish(Status.DONE, f"stopped on contact: {felt}")

    def sense(self, readings: Readings, leg: np.ndarray, dt: float) -> None:
        """Watch the sensors on the way along `leg` (world frame); a plain move has nothing to watch."""

    def arrived(self, distance: float) -> None:
        self.finish(Status.DONE, f"reached the target ({distance * 1000:.1f} mm)")

    def _line(self, position: np.ndarray, goal: np.ndarray) -> np.ndarray:
        """Along the straight line from the leg's start to its goal, pulled back onto it."""
        _, length, u = self._leg(goal)
        if u is None:
            return clamp_norm(GAIN * (goal - position), self.max_speed)
        s = float((position - self.leg_start).dot(u))
        on_line = self.leg_start + min(max(s, 0.0), length) * u
        along = max(-self.max_speed, min(self.max_speed, GAIN * (length - s)))
        return clamp_norm(u * along + GAIN * (on_line - position), self.max_speed)

    def _leg(self, goal: np.ndarray) -> tuple[np.ndarray, float, np.ndarray | None]:
        """The leg from its start to `goal`: its vector, its length and its direction (None on a
        leg of no length), worked out once a leg rather than every tick."""
        line = self._leg_line
        if line is None or line[0] is not self.leg_start or line[1] is not goal:
            leg = goal - self.leg_start
            length = norm(leg)
            line = self._leg_line = (self.leg_start, goal, leg, length, leg / length if length >= 1e-6 else None)
        return line[2:]

    def _stay(self, readings: Readings) -> ControlData:
        if self.rest is None:
            return arm_output(np.zeros(6))
        w, _ = orientation_twist(self.rotation, readings.tcp[:3, :3])
        return arm_output(np.concatenate([GAIN * (self.rest - readings.tcp[:3, 3]), w]))


class Push(CartesianMove):
    """Push the object along the path (Table 7.1 push): a guarded move that must feel it.

    A hand that passes the object by (over it, around it) reaches the target as a plain
    move would; so the push succeeds only if the wrist has felt the object resist the
    motion. The wrist also reads the arm's own dynamics in free motion (inertia while the
    TCP speeds up, and a steady drag that differs per robot and speed), so the push force
    is the force against the motion over its free-motion level, measured over
    baseline_time once the TCP cruises (once, on the first leg), low-passed over push_time,
    and read only while the TCP cruises. An object that resists with force_threshold is
    stuck: the push fails.
    """

    def __init__(self, ctx: Context) -> None:
        super().__init__(ctx)
        p = self.params
        self.push_force = float(p["push_force"])
        self.baseline_time = float(p["baseline_time"])
        self.level = LowPass(float(p["push_time"]))
        self.cruise_speed = CRUISE * self.max_speed
        self.baseline_sum = 0.0
        self.baseline_for = 0.0  # s of free motion measured so far
        self.last_position: np.ndarray | None = None
        self.pushed = 0.0  # the strongest push level so far, N

    def sense(self, readings: Readings, leg: np.ndarray, dt: float) -> None:
        position = readings.tcp[:3, 3]
        speed = 0.0 if self.last_position is None else norm(position - self.last_position) / dt
        self.last_position = position.copy()
        length = norm(leg)
        if length < 1e-6:
            return
        if speed < self.cruise_speed:  # speeding up or slowing down: the hand's inertia reads as force
            return
        against = -float((readings.tcp[:3, :3] @ self.contact.value[:3]) @ leg) / length
        if self.baseline_for < self.baseline_time:
            self.baseline_sum += against * dt
            self.baseline_for += dt
            self.level.reset(np.zeros(1))
            return
        level = float(self.level(np.array([against - self.baseline_sum / self.baseline_for]), dt)[0])
        self.pushed = max(self.pushed, level)

    def stopped_by(self, force: float, short: float) -> None:
        self.finish(Status.ERROR, f"the object does not give way: |F| = {force:.1f} N >= {self.threshold:g} N")

    def arrived(self, distance: float) -> None:
        if self.baseline_for < self.baseline_time:
            self.finish(Status.ERROR, f"reached the target before measuring the free-motion force "
                                      f"({self.baseline_time:g} s at {self.cruise_speed:g} m/s or more): "
                                      f"start the push further from the object")
        elif self.pushed < self.push_force:
            self.finish(Status.ERROR, f"reached the target without pushing anything: at most {self.pushed:.2f} N "
                                      f"against the motion, {self.push_force:g} N needed")
        else:
            self.finish(Status.DONE, f"pushed the object to the target ({distance * 1000:.1f} mm; "
                                     f"up to {self.pushed:.2f} N against the motion)")
