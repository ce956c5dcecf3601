"""The Katana gripper's controller, pure (no rospy): what katana_gazebo_plugins'
``libgazebo_ros_katana_gripper.so`` does inside Gazebo, with a GripperCommand-style goal.

Both finger joints (``katana_r_finger_joint``, ``katana_l_finger_joint``; 0.30 rad open,
-0.44 rad closed, katana_description's limits) get the same angle set-point. The set-point moves
towards the goal at most ``speed`` rad/s (the joints' velocity limit), a PD turns the error into a
torque, and the torque is clamped to the goal's ``max_effort`` (never above ``max_torque``, the
plugin's force limit). A goal ends when

* both fingers are within ``goal_tolerance`` of the goal: ``reached_goal``;
* the set-point has arrived but neither finger has moved more than ``stall_motion`` for
  ``stall_time``: ``stalled`` (the fingers press on something);
* ``timeout`` seconds have passed (katana_gazebo_plugins' GRIPPER_OPENING_CLOSING_DURATION, 6 s).

An object is held when the fingers stalled on the way to closing above
``presence_threshold`` (katana_gazebo_plugins' gripper_object_presence_threshold, -0.43 rad).
"""
import math

from katana_sim.errors import ConfigError

OPEN_ANGLE = 0.30
CLOSED_ANGLE = -0.44
PRESENCE_THRESHOLD = -0.43


class GripperResult(object):
    """control_msgs/GripperCommandResult's fields plus ``holding`` and a reason."""
    __slots__ = ("position", "effort", "stalled", "reached_goal", "holding", "text")

    def __init__(self, position, effort, stalled, reached_goal, holding, text):
        self.position, self.effort = position, effort
        self.stalled, self.reached_goal, self.holding, self.text = stalled, reached_goal, holding, text


class GripperController(object):
    """``update(t, dt, positions, velocities) -> efforts`` for the two finger joints."""

    def __init__(self, max_torque=0.5, p=3.0, d=0.02, speed=0.7, goal_tolerance=0.01,
                 stall_motion=0.004, stall_time=0.3, timeout=6.0,
                 lower=CLOSED_ANGLE, upper=OPEN_ANGLE, presence_threshold=PRESENCE_THRESHOLD):
        for name, v in (("max_torque", max_torque), ("p", p), ("speed", speed)):
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise ConfigError("gripper %s must be a positive number, got %r" % (name, v))
        self.max_torque, self.p, self.d = float(max_torque), float(p), float(d)
        self.speed, self.goal_tolerance = float(speed), float(goal_tolerance)
        self.stall_motion, self.stall_time, self.timeout = stall_motion, stall_time, timeout
        self.lower, self.upper, self.presence_threshold = lower, upper, presence_threshold
        self.setpoint = None          # current (ramped) set-point, None until the first update
        self.goal = None              # final angle of the active goal (or the hold angle)
        self.effort_limit = self.max_torque
        self.active = False           # a goal is running
        self.closing = False          # the last goal closed the gripper
        self.result = None            # GripperResult of the last finished goal
        self._start = None
        self._still_since = None
        self._still_at = None
        self._pending = None
        self.efforts = (0.0, 0.0)
        self.positions = (0.0, 0.0)

    # -- goals (the ROS layer calls these under its lock) -------------------------------------
    def command(self, position, max_effort=0.0):
        """Start a goal: ``position`` finger angle (rad), ``max_effort`` torque limit per finger
        (N m; <= 0 means the plugin's max_torque). Returns (accepted, text)."""
        if not (isinstance(position, (int, float)) and math.isfinite(position)):
            return False, ("gripper command position %r is not a finite number (rad, %.2f closed .. "
                           "%.2f open)" % (position, self.lower, self.upper))
        if not (isinstance(max_effort, (int, float)) and math.isfinite(max_effort)):
            return False, "gripper command max_effort %r is not a finite number (N m; 0 = %.2f)" % (
                max_effort, self.max_torque)
        text = ""
        target = min(max(float(position), self.lower), self.upper)
        if target != position:
            text = "position %.3f clamped to the finger limits [%.2f, %.2f]" % (
                position, self.lower, self.upper)
        limit = self.max_torque if max_effort <= 0 else min(float(max_effort), self.max_torque)
        self._pending = (target, limit)
        return True, text

    def cancel(self, t):
        """Stop the active goal where the fingers are."""
        if self.active:
            self.goal = self.setpoint
            self.active = False
            self.result = self._make_result(False, False, "cancelled")

    # -- simulation loop -----------------------------------------------------------------------
    def update(self, t, dt, positions, velocities):
        self.positions = tuple(positions)
        mean = 0.5 * (positions[0] + positions[1])
        if self.setpoint is None:
            # start-up: open (the real gripper opens when the arm is calibrated), from where it is
            self.setpoint = mean
            self.goal = self.upper
        if self._pending is not None:
            target, limit = self._pending
            self._pending = None
            self.closing = target < mean
            self.goal, self.effort_limit = target, limit
            self.active, self.result = True, None
            self._start, self._still_since = t, None
        step = self.speed * dt
        delta = self.goal - self.setpoint
        self.setpoint += max(-step, min(step, delta))
        efforts = []
        for q, v in zip(positions, velocities):
            e = self.p * (self.setpoint - q) - self.d * v
            efforts.append(max(-self.effort_limit, min(self.effort_limit, e)))
        self.efforts = tuple(efforts)
        if self.active:
            self._check(t, positions, velocities)
        return self.efforts

    def _check(self, t, positions, velocities):
        arrived = abs(self.setpoint - self.goal) < 1e-12
        if arrived and all(abs(q - self.goal) < self.goal_tolerance for q in positions):
            self.active = False
            self.result = self._make_result(False, True, "reached %.3f rad" % self.goal)
            return
        # still: neither finger moved more than stall_motion over the last stall_time (contact
        # chatter makes the instantaneous velocity a poor test)
        still = False
        if arrived:
            if self._still_since is None or any(abs(q - q0) > self.stall_motion
                                                for q, q0 in zip(positions, self._still_at)):
                self._still_since, self._still_at = t, tuple(positions)
            elif t - self._still_since >= self.stall_time:
                still = True
                self.active = False
                self.result = self._make_result(True, False, "stalled at %.3f rad (goal %.3f)" % (
                    0.5 * sum(positions), self.goal))
                return
        if t - self._start > self.timeout:
            self.active = False
            self.result = self._make_result(still, False, "timed out after %.1f s at %.3f rad (goal %.3f)"
                                            % (self.timeout, 0.5 * sum(positions), self.goal))

    def _make_result(self, stalled, reached, text):
        mean = 0.5 * (self.positions[0] + self.positions[1])
        holding = bool(stalled and self.closing and mean > self.presence_threshold)
        effort = 0.5 * (abs(self.efforts[0]) + abs(self.efforts[1]))
        return GripperResult(mean, effort, stalled, reached, holding, text)

    def holding(self):
        """Whether an object is held now (the grasp query of katana_gazebo_plugins)."""
        mean = 0.5 * (self.positions[0] + self.positions[1])
        return bool(self.closing and not self.active and self.result is not None and self.result.stalled
                    and mean > self.presence_threshold)
