"""position_controllers/GripperActionController and effort_controllers/GripperActionController
(ros_controllers' gripper_action_controller, Noetic), pure.

One joint (``joint``) driven to the position of a control_msgs/GripperCommand goal
(``command.position``, ``command.max_effort``) on the ``gripper_cmd`` action. Parameters:

  joint                      required
  goal_tolerance             0.01: |position error| below it -> the goal succeeds, reached_goal
  max_effort                 0: the max_effort the controller holds with when no goal is active
  stall_velocity_threshold   0.001: slower than this the joint counts as not moving
  stall_timeout              1.0 s: not moving for longer (and not at the goal) -> the goal is
                             aborted with stalled: true (the fingers press on something)
  action_monitor_rate        20 Hz
  gains/<joint>              effort type only, required: PID {p, i, d, i_clamp, ...}

What the joint gets, as ros_controllers' HardwareInterfaceAdapter: the position type writes the goal
position to the position interface (the hardware takes it there: kinematically, or through
``gazebo_ros_control/pid_gains``); the effort type writes PID(position error, velocity error)
clamped to +-|max_effort| -- so a max_effort of 0 applies no effort at all, exactly as there (the
ROS layer warns about such a goal). That PID is the joint's actuator (SEGMENT_PID holding the target,
run by the World at every step). The goal's checks (success, stall) are ros_controllers' checks at
every update; here the joint's actuator watches for them (Actuator.watch): the World steps natively
until the step at which one of them would fire and the update runs in Python there, so a goal ends
at the same step as with an update at every step. Otherwise updates run when something changes.

Outcomes (``events``: (goal id, outcome, result dict, text)), as ros_controllers reports them:
succeeded with ``reached_goal: true`` once within goal_tolerance; aborted with ``stalled: true``
after stall_timeout without movement; a new goal preempts the active one; cancel holds where the
joint is (with the parameter's max_effort); stopping the controller preempts its goal. The result's
``position`` is the joint's, ``effort`` the last command computed (the effort type's clamped PID
output; for the position type the goal's max_effort, as ros_controllers returns it).
"""
import math

from modrob_sim.errors import ControllerError
from modrob_sim.physics import actuators
from modrob_sim.ros_control.controllers.base import CommandBuffer, Controller
from modrob_sim.ros_control.pid import Pid, PidGains
from modrob_sim.ros_control.transmissions import EFFORT, POSITION


class GripperActionControllerBase(Controller):
    def __init__(self, name, hw, params):
        super(GripperActionControllerBase, self).__init__(name, hw, params)
        joint = params.get("joint", kind=str)
        self.joint = hw.joint(joint, self.INTERFACE, controller=name)
        self.joint_names = [joint]
        self.goal_tolerance = abs(params.get("goal_tolerance", 0.01, kind=float))
        self.default_max_effort = abs(params.get("max_effort", 0.0, kind=float))
        self.stall_velocity_threshold = params.get("stall_velocity_threshold", 0.001, kind=float)
        self.stall_timeout = params.get("stall_timeout", 1.0, kind=float)
        self.action_monitor_rate = params.get("action_monitor_rate", 20.0, kind=float)
        if self.action_monitor_rate <= 0.0:
            raise ControllerError("Parameter %s must be > 0" % params.path("action_monitor_rate"))
        #: (position, max_effort) the update drives to; ROS callbacks may write it
        self.target = CommandBuffer((self.joint.position, self.default_max_effort))
        self.goal = None
        self.events = []
        self.computed_command = 0.0
        self._last_movement = 0.0
        self._watch_act = None      # the actuator watching the goal's checks (None: every update)

    # -- goals (loop thread) ---------------------------------------------------------------
    def check_goal(self, position, max_effort):
        """'' or why a GripperCommand cannot be followed (pure, any thread)."""
        for what, v in (("command.position", position), ("command.max_effort", max_effort)):
            try:
                v = float(v)
            except (TypeError, ValueError):
                return "%s %r is not a number" % (what, v)
            if not math.isfinite(v):
                return "%s %r of joint '%s' is not finite" % (what, v, self.joint.name)
        return ""

    def notes(self, position, max_effort):
        """Warnings about an accepted goal that will not do what its sender may think."""
        out = []
        j = self.joint
        if j.has_position_limits and not (j.lower <= position <= j.upper):
            out.append("position %g is outside the limits [%g, %g] of joint '%s': the joint stops at the "
                       "limit and the goal ends stalled" % (position, j.lower, j.upper, j.name))
        return out

    def submit(self, goal_id, position, max_effort, now):
        """A GripperCommand goal: (accepted, text). Accepting preempts the active goal."""
        if self.state != "running":
            return False, "Can't accept new action goals. Controller '%s' is not running." % self.name
        bad = self.check_goal(position, max_effort)
        if bad:
            return False, bad
        self._preempt("preempted by a new goal")
        self.target.write((float(position), float(max_effort)))
        self.goal = goal_id
        self._last_movement = now
        return True, ""

    def cancel(self, goal_id, now):
        """Cancel the active goal: hold where the joint is."""
        if self.goal is None or self.goal != goal_id:
            return False
        self.goal = None
        self._watch(None)
        self.target.write((self.joint.position, self.default_max_effort))
        self.events.append((goal_id, "canceled", self._result(False, False), "canceled"))
        return True

    def _preempt(self, text):
        if self.goal is not None:
            self.events.append((self.goal, "preempted", self._result(False, False), text))
            self.goal = None

    def _result(self, reached, stalled):
        return dict(position=self.joint.position, effort=self._last_command(), stalled=stalled,
                    reached_goal=reached)

    # -- controller ------------------------------------------------------------------------
    def starting(self, t):
        self.target.write((self.joint.position, self.default_max_effort))
        self._last_movement = t
        self._start_adapter()

    def stopping(self, t):
        self._preempt("controller '%s' was stopped" % self.name)
        self._watch(None)

    def update(self, t, dt):
        self._taken_target = self.target.version
        position, max_effort = self.target.read()
        error = position - self.joint.position
        velocity = self.joint.velocity
        w = self._watch_act
        if w is not None and self.goal is not None:     # the steps the World made natively moved it
            self._last_movement = max(self._last_movement, w.moved_at)
        self._check(t, error, velocity)
        self.computed_command = self._command(dt, position, error, -velocity, max_effort)
        self._watch(position)

    def _last_command(self):
        """The command the joint got in the last step (ros_controllers' computed_command_ of the
        update before: its result's ``effort``)."""
        return self.computed_command

    def _watched_actuator(self):
        """The joint's actuator that can watch the goal's checks (None: the update checks them at
        every step)."""
        return self.joint.actuator

    def _watch(self, position):
        """The goal's checks to the joint's actuator (none without a goal)."""
        a = self._watched_actuator() if self.goal is not None else None
        if self._watch_act is not None and self._watch_act is not a:
            self._watch_act.unwatch()
        self._watch_act = a
        if a is not None:
            a.watch(position, self.goal_tolerance, self.stall_velocity_threshold, self.stall_timeout,
                    self._last_movement)

    def _check(self, t, error, velocity):
        if self.goal is None:
            return
        if abs(error) < self.goal_tolerance:
            self.events.append((self.goal, "succeeded", self._result(True, False), "reached the goal"))
            self.goal = None
        elif abs(velocity) > self.stall_velocity_threshold:
            self._last_movement = t
        elif t - self._last_movement > self.stall_timeout:
            self.events.append((self.goal, "aborted", self._result(False, True),
                                "stalled %.3g from the goal position: joint '%s' has not moved for %g s"
                                % (error, self.joint.name, self.stall_timeout)))
            self.goal = None

    #: the ``target`` buffer's version the last update took
    _taken_target = None

    def update_due(self, t, iteration, dt):
        """While a goal runs, the step at which its checks fire (the joint's actuator watches for
        it: the World ends its native stretch there), or every update where no actuator can watch;
        otherwise only when a new target waits: the hardware (or the effort type's actuator) holds
        the last one."""
        if self.target.version != self._taken_target:
            return t
        if self.goal is not None:
            w = self._watch_act
            if w is None or not w.watching or w is not self._watched_actuator():
                return t
        return float("inf")

    def _start_adapter(self):
        pass

    def _command(self, dt, position, error, error_velocity, max_effort):
        raise NotImplementedError


class PositionGripperActionController(GripperActionControllerBase):
    TYPE = "position_controllers/GripperActionController"
    INTERFACE = POSITION

    def _watched_actuator(self):
        j = self.joint
        return j.actuator if j.owner is None else None     # the hardware's (kinematic or pid_gains)

    def _command(self, dt, position, error, error_velocity, max_effort):
        self.joint.command = position
        return max_effort


class EffortGripperActionController(GripperActionControllerBase):
    TYPE = "effort_controllers/GripperActionController"
    INTERFACE = EFFORT

    def __init__(self, name, hw, params):
        super(EffortGripperActionController, self).__init__(name, hw, params)
        gains = params.child("gains", required=True)
        self.pid = Pid(PidGains.from_params(gains.child(self.joint.name, required=True)))
        self.pid_namespace = gains.path(self.joint.name)

    def notes(self, position, max_effort):
        out = super(EffortGripperActionController, self).notes(position, max_effort)
        if max_effort == 0.0:
            out.append("max_effort 0: %s clamps its PID's effort to +-max_effort, so joint '%s' gets no "
                       "effort and the goal ends stalled (as in ros_controllers); give command.max_effort"
                       % (self.TYPE, self.joint.name))
        return out

    def _watched_actuator(self):
        return self.act if self.joint.owner is self else None

    def _last_command(self):
        # the effort the PID gave in the last step the actuator made (with the updates in between
        # made natively, the update before is long ago)
        return self._clamped(self.act.last.output, self._max_effort)

    def _start_adapter(self):
        self.pid.reset()
        # the PID (position error, velocity error = -velocity) runs in the joint's actuator at
        # every step, holding the target; its output clamped to +-max_effort (and the joint's
        # effort limit: the two symmetric clamps in one)
        self.joint.command = 0.0
        self.act = self.joint.actuate(actuators.SEGMENT_PID, self.pid.gains, actuators.PLAIN, owner=self)
        self._gains = self.pid.gains
        self._max_effort = 0.0
        self.act.hold(self.joint.position)
        self.act.effort_limit = 0.0

    def stopping(self, t):
        super(EffortGripperActionController, self).stopping(t)
        if self.joint.owner is self:
            # the hardware keeps applying the last effort, as ros_control's does
            self.joint.command = self._clamped(self.act.last.output, self._max_effort)
            self.joint.release()

    def update_due(self, t, iteration, dt):
        if self.pid.gains is not self._gains:
            return t
        return super(EffortGripperActionController, self).update_due(t, iteration, dt)

    def _clamped(self, effort, max_effort):
        lim = abs(max_effort)
        return min(lim, max(-lim, effort))

    def _command(self, dt, position, error, error_velocity, max_effort):
        a = self.act
        if self.pid.gains is not self._gains:
            self._gains = a.gains = self.pid.gains
        a.hold(position)
        self._max_effort = max_effort
        lim = abs(max_effort)
        hw = self.joint.effort_limit
        a.effort_limit = lim if hw is None else min(lim, hw)
        # what ros_controllers reports as the command: the clamped PID output (of the last step
        # the actuator made; this update's step follows)
        return self._clamped(a.last.output, max_effort)
