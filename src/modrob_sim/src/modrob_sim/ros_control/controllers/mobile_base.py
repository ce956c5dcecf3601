"""What ros_controllers' mobile base controllers (diff_drive_controller, ackermann_steering_controller,
Noetic) share: the twist command with its timeout, the speed limiter, odometry from wheel travel,
and the odometry message's schedule, frames and covariances.

Parameters (under the controller's namespace; defaults as ros_controllers):

==================================== =========== ==============================================
``publish_rate``                     50.0        odometry (and odom tf) per second
``open_loop``                        false       odometry from the commands, not the wheels
``velocity_rolling_window_size``     10          updates averaged for the odometry's twist
``cmd_vel_timeout``                  0.5         s after the last command: brake
``allow_multiple_cmd_vel_publishers`` true       false: brake while two nodes publish
``base_frame_id`` / ``odom_frame_id`` base_link / odom
``enable_odom_tf``                   true        odom -> base transform on /tf
``pose_covariance_diagonal``,        (required)  6 numbers each: the diagonal of the odometry's
``twist_covariance_diagonal``                    pose and twist covariance
``linear/x/...``, ``angular/z/...``  no limits   ``has_velocity_limits``, ``has_acceleration_limits``,
                                                 ``has_jerk_limits``, ``max_*`` (0) and ``min_*``
                                                 (default ``-max_*``) for velocity, acceleration, jerk
==================================== =========== ==============================================

Unknown parameters are ignored, as ros_controllers does (Jackal's YAML carries ``k_l``/``k_r``).
"""
import collections
import itertools
import math

from modrob_sim.errors import ControllerError
from modrob_sim.physics.due import IdleLook
from modrob_sim.ros_control.controllers.base import CommandBuffer, CommandResult, Controller
from modrob_sim.ros_control.transmissions import CPP_NAMES

DEFAULT_PUBLISH_RATE = 50.0
DEFAULT_WINDOW = 10
DEFAULT_CMD_VEL_TIMEOUT = 0.5


class SpeedLimiter(object):
    """diff_drive_controller's SpeedLimiter: jerk, then acceleration, then velocity limits on one
    command, from the two previous commands ``v0`` (last) and ``v1`` (the one before)."""

    KINDS = ("velocity", "acceleration", "jerk")

    def __init__(self, **kw):
        for kind in self.KINDS:
            setattr(self, "has_%s_limits" % kind, bool(kw.get("has_%s_limits" % kind, False)))
            mx = float(kw.get("max_" + kind, 0.0))
            setattr(self, "max_" + kind, mx)
            setattr(self, "min_" + kind, float(kw.get("min_" + kind, -mx)))

    @classmethod
    def from_params(cls, params):
        """From a namespace such as ``<controller>/linear/x``; every key optional."""
        kw = {}
        for kind in cls.KINDS:
            key = "has_%s_limits" % kind
            if params.has(key):
                kw[key] = params.get(key, kind=bool)
            for bound in ("max_", "min_"):
                if params.has(bound + kind):
                    kw[bound + kind] = params.get(bound + kind, kind=float)
        return cls(**kw)

    def limit(self, v, v0, v1, dt):
        if self.has_jerk_limits:
            # ros_controllers bounds the change of the step by jerk * 2 dt^2; kept as written there
            dv, dv0 = v - v0, v0 - v1
            da = min(max(dv - dv0, self.min_jerk * 2.0 * dt * dt), self.max_jerk * 2.0 * dt * dt)
            v = v0 + dv0 + da
        if self.has_acceleration_limits:
            v = v0 + min(max(v - v0, self.min_acceleration * dt), self.max_acceleration * dt)
        if self.has_velocity_limits:
            v = min(max(v, self.min_velocity), self.max_velocity)
        return v


class Odometry(object):
    """Pose (x, y, heading) integrated from per-update travel (distance, heading change), exactly
    along the arc when it turns; the twist is the rolling mean over ``window`` updates."""

    def __init__(self, window=DEFAULT_WINDOW):
        self.window = max(1, int(window))
        self.reset()

    def reset(self, t=None):
        self.x = self.y = self.heading = 0.0
        self.linear = self.angular = 0.0
        self.time = t
        self._lin = collections.deque(maxlen=self.window)
        self._ang = collections.deque(maxlen=self.window)

    def restart(self, t):
        """ros_controllers' Odometry::init: the twist averages and the time start again; the pose
        stays where it is."""
        self.time = t
        self._lin.clear()
        self._ang.clear()

    def integrate(self, distance, dheading):
        if abs(dheading) < 1e-6:
            mid = self.heading + 0.5 * dheading          # second-order Runge-Kutta
            self.x += distance * math.cos(mid)
            self.y += distance * math.sin(mid)
        else:
            r = distance / dheading
            old = self.heading
            self.x += r * (math.sin(old + dheading) - math.sin(old))
            self.y -= r * (math.cos(old + dheading) - math.cos(old))
        self.heading += dheading

    def update(self, distance, dheading, t):
        """Travel since the last update, measured at time ``t``."""
        self.integrate(distance, dheading)
        dt = t - self.time if self.time is not None else 0.0
        if dt < 1e-4:          # too short an interval for a speed (as ros_controllers)
            return
        self.time = t
        self._lin.append(distance / dt)
        self._ang.append(dheading / dt)
        self.linear = sum(self._lin) / len(self._lin)
        self.angular = sum(self._ang) / len(self._ang)

    def update_open_loop(self, linear, angular, t):
        dt = t - self.time if self.time is not None else 0.0
        self.time = t
        self.linear, self.angular = linear, angular
        self.integrate(linear * dt, angular * dt)


def covariance_diagonal(params, name):
    path = params.path(name)
    if not params.has(name):
        raise ControllerError("Parameter %s is missing: the odometry needs it, 6 numbers for x y z roll "
                              "pitch yaw (e.g. '%s: [0.001, 0.001, 1000000.0, 1000000.0, 1000000.0, 0.03]')"
                              % (path, name))
    values = params.get(name)
    if (not isinstance(values, list) or len(values) != 6
            or not all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
                       for v in values)):
        raise ControllerError("Parameter %s must be a list of 6 finite numbers (x y z roll pitch yaw), "
                              "got %r" % (path, values))
    return [float(v) for v in values]


def full_covariance(diagonal):
    """The 6x6 row-major covariance with ``diagonal`` on its diagonal."""
    cov = [0.0] * 36
    for i, v in enumerate(diagonal):
        cov[7 * i] = v
    return cov


def positive(params, name, default):
    value = params.get(name, default, kind=float)
    if value <= 0.0:
        raise ControllerError("Parameter %s must be > 0, got %g" % (params.path(name), value))
    return value


class MobileBaseController(Controller):
    """A controller that takes ``cmd_vel`` (linear x, angular z) and publishes odometry.

    ``pending`` after an update that publishes: dict(stamp, x, y, heading, linear, angular).
    ``cmd_out`` after every update: (stamp, linear, angular) the limited command that was sent.
    ``per_update_wanted()``: whether someone listens to the messages of every update
    (``publish_cmd``, ``publish_wheel_state``); the ROS layer sets it from its topics' subscribers.
    """

    #: its update runs wherever the control loop updates, due or not: the odometry's pose sums one
    #: arc per update (so the arcs, and the pose's last digits, follow every update), and an update
    #: looks for a listener of the per-update messages (where the messages start)
    update_at_every_stop = True

    def __init__(self, name, hw, params):
        super(MobileBaseController, self).__init__(name, hw, params)
        self.publish_rate = positive(params, "publish_rate", DEFAULT_PUBLISH_RATE)
        self.open_loop = params.get("open_loop", False, kind=bool)
        window = params.get("velocity_rolling_window_size", DEFAULT_WINDOW)
        if isinstance(window, bool) or not isinstance(window, int) or window < 1:
            raise ControllerError("Parameter %s must be a whole number >= 1, got %r"
                                  % (params.path("velocity_rolling_window_size"), window))
        self.odometry = Odometry(window)
        self.cmd_vel_timeout = params.get("cmd_vel_timeout", DEFAULT_CMD_VEL_TIMEOUT, kind=float)
        self.allow_multiple_publishers = params.get("allow_multiple_cmd_vel_publishers", True, kind=bool)
        self.base_frame_id = params.get("base_frame_id", "base_link", kind=str)
        self.odom_frame_id = params.get("odom_frame_id", "odom", kind=str)
        self.enable_odom_tf = params.get("enable_odom_tf", True, kind=bool)
        self.pose_covariance = full_covariance(covariance_diagonal(params, "pose_covariance_diagonal"))
        self.twist_covariance = full_covariance(covariance_diagonal(params, "twist_covariance_diagonal"))
        self.limiter_linear = SpeedLimiter.from_params(params.child("linear").child("x"))
        self.limiter_angular = SpeedLimiter.from_params(params.child("angular").child("z"))
        self.publish_cmd = params.get("publish_cmd", False, kind=bool)
        #: diff_drive_controller's publish_wheel_joint_controller_state (DiffDriveController's):
        #: then after each update ``wheel_state`` = dict(stamp, desired positions (the commanded
        #: speeds integrated), desired velocities, desired accelerations)
        self.publish_wheel_state = False
        self.wheel_state = None
        self.per_update_wanted = lambda: True
        #: while nobody listens to the per-update messages: the next look for a listener
        self.listeners = IdleLook()
        # (linear, angular, sequence number); the update stamps a new command when it first sees it
        self._numbers = itertools.count(1)     # next() is atomic: ROS threads and the loop both write
        self.command = CommandBuffer((0.0, 0.0, 0))
        self._seen_seq = 0
        self._cmd_stamp = -math.inf
        self._last0 = (0.0, 0.0)
        self._last1 = (0.0, 0.0)
        self._last_publish = None
        self._fresh = True
        self.cmd_out = None

    # -- what the subclasses give ---------------------------------------------------------------
    def interfaces(self):
        """[(interface, [joint names])]: what the controller claims."""
        raise NotImplementedError

    def measure(self):
        """(distance, heading change) since the last call, from the joints; None to skip."""
        raise NotImplementedError

    def drive(self, linear, angular):
        """Write the joint commands for the (limited) body command."""
        raise NotImplementedError

    # -- the contract -----------------------------------------------------------------------------
    @property
    def claimed_resources(self):
        return [(CPP_NAMES[iface], list(joints)) for iface, joints in self.interfaces()]

    def set_command(self, linear, angular):
        """A ``cmd_vel`` message (linear.x, angular.z). Called from ROS threads."""
        for what, v in (("linear.x", linear), ("angular.z", angular)):
            try:
                ok = math.isfinite(float(v))
            except (TypeError, ValueError):
                ok = False
            if not ok:
                return CommandResult(False, reason="velocity command %s = %r is not finite: ignored"
                                     % (what, v))
        self.command.write((float(linear), float(angular), next(self._numbers)))
        return CommandResult(True, (float(linear), float(angular)))

    def brake(self):
        """Zero command now (also what a stale or forbidden command turns into)."""
        self.command.write((0.0, 0.0, next(self._numbers)))

    def starting(self, t):
        self.brake()
        self._seen_seq = self.command.read()[2]
        self._cmd_stamp = -math.inf
        self._last0 = self._last1 = (0.0, 0.0)
        self._last_publish = t
        self.odometry.restart(t)
        self.drive(0.0, 0.0)
        self._fresh = True      # the first update writes the stopped wheels' commands
        self.listeners.reset()

    def stopping(self, t):
        self.drive(0.0, 0.0)

    def _publish_time(self):
        """The time after which an update publishes odometry (inf: never, publish_rate 0)."""
        rate = self.publish_rate
        if rate <= 0.0:
            return math.inf
        return -math.inf if self._last_publish is None else self._last_publish + 1.0 / rate

    def _target(self, t):
        """The (linear, angular) an update at ``t`` would ask for before the limiters."""
        lin, ang, _seq = self.command.read()
        if t - self._cmd_stamp > self.cmd_vel_timeout:
            return 0.0, 0.0
        return lin, ang

    def update_due(self, t, iteration, dt):
        """An update in Python when it changes something or publishes; between those the joints'
        hardware holds the wheel commands (docs/controllers.md, "When controllers run"):

        * a new command waits, or the limited command has not reached its target (the limiters
          work per update, so a ramp is made at every step), or ``publish_cmd`` /
          ``publish_wheel_joint_controller_state`` while someone listens (a message at every
          update);
        * while nobody listens to those: a look for a listener every ``IDLE_LOOK`` (physics.due),
          as the sensors look; the messages start at the update that finds one;
        * the command's timeout (``cmd_vel_timeout`` after it came): the brake;
        * the odometry: the update that publishes and the ``velocity_rolling_window_size`` + 1
          updates before it, at every step, so that the twist averages per-step speeds exactly
          as at every update (the pose integrates the travel since the last update along an arc,
          equal to the per-step sums to rounding)."""
        if self._fresh:
            return t
        due = math.inf
        if self.publish_cmd or self.publish_wheel_state:
            if self.listeners.until is None:
                return t
            due = self.listeners.until
        if self.command.read()[2] != self._seen_seq:
            return t
        target = self._target(t)
        if self._last0 != target or self._last1 != target:
            return t
        if target != (0.0, 0.0):
            due = min(due, self._cmd_stamp + self.cmd_vel_timeout - 0.5 * dt)
        publish = self._publish_time()
        if publish < math.inf:
            # the first step starting after `publish`, less the window and one step of margin
            steps = math.floor((publish - t) / dt) + 1 if publish >= t else 0
            due = min(due, t + (steps - self.odometry.window - 1.5) * dt)
        return t if due <= t else due

    def update(self, t, dt):
        self._fresh = False
        if self.publish_cmd or self.publish_wheel_state:
            self.listeners.look(t, self.per_update_wanted())
        odo = self.odometry
        if self.open_loop:
            odo.update_open_loop(self._last0[0], self._open_loop_rate(*self._last0), t)
        else:
            travel = self.measure()
            if travel is None:
                return
            odo.update(travel[0], travel[1], t)
        rate = self.publish_rate          # changed live by dynamic_reconfigure; 0: no odometry
        period = 1.0 / rate if rate > 0.0 else math.inf
        if rate > 0.0 and (self._last_publish is None or self._last_publish + period < t):
            # whole periods, so that the average rate is exact; a long gap starts afresh
            if self._last_publish is None or t - self._last_publish > 2.0 * period:
                self._last_publish = t
            else:
                self._last_publish += period
            self.pending = dict(stamp=t, x=odo.x, y=odo.y, heading=odo.heading, linear=odo.linear,
                                angular=odo.angular)
        lin, ang, seq = self.command.read()
        if seq != self._seen_seq:
            self._seen_seq = seq
            self._cmd_stamp = t
        if t - self._cmd_stamp > self.cmd_vel_timeout:
            lin = ang = 0.0
        lin = self.limiter_linear.limit(lin, self._last0[0], self._last1[0], dt)
        ang = self.limiter_angular.limit(ang, self._last0[1], self._last1[1], dt)
        self._last1, self._last0 = self._last0, (lin, ang)
        self.cmd_out = (t, lin, ang)
        self.drive(lin, ang)

    def _open_loop_rate(self, linear, angular):
        """The heading rate open-loop odometry integrates for the last command."""
        return angular
