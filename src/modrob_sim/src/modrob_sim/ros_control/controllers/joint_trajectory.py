"""position_controllers/, velocity_controllers/ and effort_controllers/JointTrajectoryController
(ros_controllers' joint_trajectory_controller, Noetic), pure.

Parameters (under the controller's namespace):
  joints                         list, required
  constraints/goal_time          default 0: how long after the trajectory's end the goal
                                 tolerances may still be met
  constraints/stopped_velocity_tolerance   default 0.01: goal velocity tolerance
  constraints/<joint>/trajectory path position tolerance (0 = none)
  constraints/<joint>/goal       goal position tolerance (0 = none)
  stop_trajectory_duration       default 0: time to come to rest on cancel/stop
  state_publish_rate             default 50 Hz (``state`` topic)
  action_monitor_rate            default 20 Hz (action feedback)
  allow_partial_joints_goal      default false
  gains/<joint>                  effort and velocity types, required: PID {p, i, d, i_clamp, ...};
                                 its output is the joint's effort or velocity command
  velocity_ff/<joint>            effort and velocity types, default 0

The ROS layer passes goals in (``submit``/``cancel``) and drains ``events`` (goal outcomes)
and ``pending``/``pending_feedback`` (state/feedback data) after each update.
"""
import math

from modrob_sim.errors import ControllerError
from modrob_sim.physics import actuators
from modrob_sim.ros_control import angles
from modrob_sim.ros_control.controllers.base import Controller
from modrob_sim.ros_control.pid import Pid, PidGains
from modrob_sim.ros_control.trajectory import (ABSOLUTE, HOLD, PreparedTrajectory, State, Trajectory,
                                               hold_trajectory)
from modrob_sim.ros_control.transmissions import EFFORT, POSITION, VELOCITY

INF = float("inf")

SUCCESSFUL = 0
INVALID_GOAL = -1
INVALID_JOINTS = -2
OLD_HEADER_TIMESTAMP = -3
PATH_TOLERANCE_VIOLATED = -4
GOAL_TOLERANCE_VIOLATED = -5

#: a goal position may exceed its joint's limit by this much (rad or m): a joint resting on its stop
#: reads slightly beyond it, and a client that sends the current state as its first point (MoveIt
#: does) must not be refused for that
LIMIT_SLACK = 1e-3
#: positions, velocities and accelerations beyond this (rad, m, /s, /s^2) are refused
MAX_VALUE = 1e6


class TrajectoryPoint(object):
    __slots__ = ("positions", "velocities", "accelerations", "time_from_start")

    def __init__(self, positions, velocities=None, accelerations=None, time_from_start=0.0):
        self.positions = list(positions)
        self.velocities = list(velocities or [])
        self.accelerations = list(accelerations or [])
        self.time_from_start = float(time_from_start)


class Tolerance(object):
    """Per-joint tolerances; 0 means 'not checked'."""
    __slots__ = ("position", "velocity", "acceleration")

    def __init__(self, position=0.0, velocity=0.0, acceleration=0.0):
        self.position, self.velocity, self.acceleration = position, velocity, acceleration


class ActiveGoal(object):
    def __init__(self, goal_id, path, goal, goal_time):
        self.goal_id, self.path, self.goal, self.goal_time = goal_id, path, goal, goal_time
        self.end_time = None
        #: a path tolerance of some joint is checked (> 0)
        self.checks_path = any(tol.position > 0.0 or tol.velocity > 0.0 for tol in path)


def _merge(default, override):
    """control_msgs/JointTolerance semantics: >0 replaces, 0 keeps the default, -1 erases."""
    if override is None or override == 0.0:
        return default
    if override < 0.0:
        return 0.0
    return override


def _unusable_tolerance(*named_lists):
    """Why a goal's tolerances cannot be used ('' when they can): a position or velocity tolerance
    that is NaN or infinite (control_msgs/JointTolerance: > 0 a tolerance, 0 the default, -1
    erased)."""
    for what, tolerances in named_lists:
        for tol in tolerances or ():
            for field in ("position", "velocity"):
                value = getattr(tol, field)
                if not math.isfinite(value):
                    return ("%s of joint '%s': %s %r is not a finite number; send a tolerance > 0, 0 for "
                            "the controller's default or -1 to erase it" % (what, tol.name, field, value))
    return ""


class JointTrajectoryControllerBase(Controller):
    INTERFACE = None

    def __init__(self, name, hw, params):
        super(JointTrajectoryControllerBase, self).__init__(name, hw, params)
        joints = params.get("joints", kind=list)
        if not joints:
            raise ControllerError("Parameter %s is empty: list the joints this trajectory controller drives"
                                  % params.path("joints"))
        if len(set(joints)) != len(joints):
            raise ControllerError("Parameter %s names a joint twice: %s" % (params.path("joints"), joints))
        self.joint_names = list(joints)
        self.joints = [hw.joint(j, self.INTERFACE, controller=name) for j in joints]
        self.n = len(joints)
        c = params.child("constraints")
        self.default_goal_time = c.get("goal_time", 0.0, kind=float)
        self.stopped_velocity_tolerance = c.get("stopped_velocity_tolerance", 0.01, kind=float)
        self.default_path = []
        self.default_goal = []
        for j in joints:
            jc = c.child(j)
            self.default_path.append(Tolerance(jc.get("trajectory", 0.0, kind=float)))
            self.default_goal.append(Tolerance(jc.get("goal", 0.0, kind=float),
                                               self.stopped_velocity_tolerance))
        self.stop_trajectory_duration = params.get("stop_trajectory_duration", 0.0, kind=float)
        self.state_publish_rate = params.get("state_publish_rate", 50.0, kind=float)
        self.action_monitor_rate = params.get("action_monitor_rate", 20.0, kind=float)
        if self.state_publish_rate <= 0.0 or self.action_monitor_rate <= 0.0:
            raise ControllerError("Parameters %s and %s must be > 0"
                                  % (params.path("state_publish_rate"), params.path("action_monitor_rate")))
        self.allow_partial = params.get("allow_partial_joints_goal", False, kind=bool)
        self.trajectory = None
        self.goal = None
        self.events = []
        self.pending_feedback = None
        self._desired = ([0.0] * self.n, [0.0] * self.n, [0.0] * self.n)
        self._next_state = None
        self._next_feedback = None
        self._now = 0.0

    # -- state -----------------------------------------------------------------------------
    @property
    def desired(self):
        """(positions, velocities, accelerations) the last update commanded."""
        return self._desired

    def _actual(self):
        return [j.position for j in self.joints], [j.velocity for j in self.joints]

    @staticmethod
    def _error_rule(joint):
        """The position error of ``joint`` (ros_controllers': the shortest angle on a continuous
        joint): an actuators rule."""
        return actuators.SHORTEST if joint.type == "continuous" else actuators.PLAIN

    def _errors(self, t, desired_pos, desired_vel):
        """(position errors, velocity errors) at ``t``: the joints' actuators' tracking errors (what
        their step at ``t`` computes, and what their band watches), else the same rule here."""
        if self.acts:
            errors = [a.tracking_error(t) for a in self.acts]
            return [e[0] for e in errors], [e[1] for e in errors]
        pos, vel = self._actual()
        errors = [actuators.tracking_error(self._error_rule(j), d, dv, q, v)
                  for j, d, dv, q, v in zip(self.joints, desired_pos, desired_vel, pos, vel)]
        return [e[0] for e in errors], [e[1] for e in errors]

    def _current_desired(self, t):
        if self.trajectory is None:
            pos, _ = self._actual()
            return pos, [0.0] * self.n, [0.0] * self.n
        return self.trajectory.sample(t)

    def _hold(self, t):
        pos, vel, _ = self._current_desired(t)
        self.trajectory = hold_trajectory(t, pos, vel, self.stop_trajectory_duration)

    def starting(self, t):
        if self.goal is not None:   # started again while running: the control loop's reset
            self.events.append((self.goal.goal_id, "aborted", INVALID_GOAL,
                                "the simulation was reset (reset_simulation or reset_world) while executing "
                                "the goal: controller '%s' holds where the joints are now" % self.name))
            self.goal = None
        self.trajectory = None
        pos, _ = self._actual()
        self.trajectory = hold_trajectory(t, pos)
        self._next_state = t
        self._next_feedback = t
        self._now = t
        self._reset_pids()

    def stopping(self, t):
        if self.goal is not None:
            self.events.append((self.goal.goal_id, "aborted", INVALID_GOAL,
                                "controller '%s' was stopped while executing the goal" % self.name))
            self.goal = None

    def _reset_pids(self):
        pass

    # -- commands --------------------------------------------------------------------------
    def submit(self, joint_names, points, start_time, now, goal_id=None, path_tolerance=None,
               goal_tolerance=None, goal_time_tolerance=0.0, checked=False, prepared=None):
        """A new trajectory (from the ``command`` topic when goal_id is None, else an action goal).
        Returns (accepted, error_code, error_string). Accepting an action goal preempts the
        previous one (an event ('preempted') is queued for it). ``checked``: check_points() has
        passed already; ``prepared``: what prepare() made of these points. A ROS callback does
        both, off the simulation loop, so that the loop only places the finished segments in
        time (O(joints)) however long the trajectory is."""
        if self.state != "running":
            return False, INVALID_GOAL, "controller '%s' is not running (state: %s)" % (self.name, self.state)
        if not checked:
            ok, code, text = self.check_points(joint_names, points)
            if not ok:
                return ok, code, text
        bad = _unusable_tolerance(("path_tolerance", path_tolerance), ("goal_tolerance", goal_tolerance))
        if bad:
            return False, INVALID_GOAL, bad
        start = start_time if start_time and start_time > 0.0 else now
        return self._after_check(joint_names, points, start, now, goal_id, path_tolerance, goal_tolerance,
                                 goal_time_tolerance, prepared)

    def check_points(self, joint_names, points):
        """The checks of a trajectory that need nothing but its joint names and points (pure, any
        thread): (ok, error_code, error_string)."""
        unknown = [j for j in joint_names if j not in self.joint_names]
        if unknown:
            return False, INVALID_JOINTS, ("joint%s %s not controlled by '%s' (its joints: %s)"
                                           % ("s" if len(unknown) > 1 else "",
                                              ", ".join("'%s'" % u for u in unknown), self.name,
                                              ", ".join(self.joint_names)))
        if len(set(joint_names)) != len(joint_names):
            return False, INVALID_JOINTS, "the goal names a joint twice: %s" % list(joint_names)
        missing = [j for j in self.joint_names if j not in joint_names]
        if missing and not self.allow_partial and points:
            return False, INVALID_JOINTS, ("the goal does not name joint%s %s of '%s' (set "
                                           "allow_partial_joints_goal "
                                           "to true to allow partial goals)"
                                           % ("s" if len(missing) > 1 else "",
                                              ", ".join("'%s'" % m for m in missing), self.name))
        k = len(joint_names)
        last_t = None
        for i, p in enumerate(points):
            for what, values in (("positions", p.positions), ("velocities", p.velocities),
                                 ("accelerations", p.accelerations)):
                if (values or what == "positions") and len(values) != k:
                    return False, INVALID_GOAL, "point %d has %d %s for %d joints" % (i, len(values), what, k)
            values = p.positions + p.velocities + p.accelerations + [p.time_from_start]
            if not all(math.isfinite(v) for v in values):
                return False, INVALID_GOAL, "point %d contains a NaN or infinite value" % i
            bad = self._unreachable(joint_names, i, p)
            if bad:
                return False, INVALID_GOAL, bad
            if p.time_from_start < 0.0:
                return False, INVALID_GOAL, ("point %d has a negative time_from_start (%g s): times "
                                             "count from the trajectory's start, 0 or later"
                                             % (i, p.time_from_start))
            if last_t is not None and p.time_from_start <= last_t:
                return False, INVALID_GOAL, ("time_from_start must increase strictly: point %d at %g s "
                                             "follows %g s"
                                             % (i, p.time_from_start, last_t))
            last_t = p.time_from_start
        return True, SUCCESSFUL, ""

    def _unreachable(self, joint_names, i, point):
        """Why point ``i`` cannot be followed ('' when it can): a position outside its joint's
        URDF limits (beyond LIMIT_SLACK), or a value beyond MAX_VALUE that the trajectory's
        polynomials cannot represent."""
        for name, q in zip(joint_names, point.positions):
            j = self.joints[self.joint_names.index(name)]
            if j.has_position_limits and not (j.lower - LIMIT_SLACK <= q <= j.upper + LIMIT_SLACK):
                return ("point %d: position %.6g of joint '%s' is outside its limits [%.6g, %.6g] (URDF "
                        "<limit lower upper>); the joint cannot get there"
                        % (i, q, name, j.lower, j.upper))
        for what, values in (("position", point.positions), ("velocity", point.velocities),
                             ("acceleration", point.accelerations)):
            for name, v in zip(joint_names, values):
                if abs(v) > MAX_VALUE:
                    return ("point %d: %s %.6g of joint '%s' is beyond +-%g, which this controller does not "
                            "represent (its trajectory polynomials would overflow)"
                            % (i, what, v, name, MAX_VALUE))
        return ""

    def _after_check(self, joint_names, points, start, now, goal_id, path_tolerance, goal_tolerance,
                     goal_time_tolerance, prepared=None):
        if points and start + points[-1].time_from_start < now:
            return False, OLD_HEADER_TIMESTAMP, ("the trajectory ended %.3f s ago (header.stamp %.3f, "
                                                 "now %.3f)"
                                                 % (now - start - points[-1].time_from_start, start, now))
        # accepted
        if goal_id is not None or self.goal is not None:
            if self.goal is not None:
                self.events.append((self.goal.goal_id, "preempted", SUCCESSFUL,
                                    "preempted by a new %s" % ("goal" if goal_id is not None else "command")))
                self.goal = None
        if not points:
            self._hold(now)
            if goal_id is not None:
                self.events.append((goal_id, "succeeded", SUCCESSFUL, "empty trajectory: holding position"))
            return True, SUCCESSFUL, ""
        self.trajectory = self._build(joint_names, points, start, now, prepared)
        if goal_id is not None:
            path, goal = [], []
            by_name_path = {t.name: t for t in (path_tolerance or [])}
            by_name_goal = {t.name: t for t in (goal_tolerance or [])}
            for i, j in enumerate(self.joint_names):
                dp, dg = self.default_path[i], self.default_goal[i]
                tp, tg = by_name_path.get(j), by_name_goal.get(j)
                path.append(Tolerance(_merge(dp.position, tp and tp.position), _merge(dp.velocity,
                                                                                      tp and tp.velocity)))
                goal.append(Tolerance(_merge(dg.position, tg and tg.position), _merge(dg.velocity,
                                                                                      tg and tg.velocity)))
            gt = goal_time_tolerance if goal_time_tolerance and goal_time_tolerance > 0 \
                else self.default_goal_time
            self.goal = ActiveGoal(goal_id, path, goal, gt)
            self.goal.end_time = self.trajectory.end_time
        return True, SUCCESSFUL, ""

    def cancel(self, goal_id, now):
        """Cancel an action goal: hold (decelerating over stop_trajectory_duration)."""
        if self.goal is not None and self.goal.goal_id == goal_id:
            self.goal = None
            self._hold(now)
            self.events.append((goal_id, "canceled", SUCCESSFUL, "canceled"))
            return True
        return False

    def prepare(self, joint_names, points):
        """Every segment of a checked trajectory, in times relative to its start (pure, any
        thread: it reads only the joints' names and types). Joints the goal does not name are
        placed by _build, which adds their current desired position."""
        index = {j: i for i, j in enumerate(joint_names)}
        cols = [index.get(j) for j in self.joint_names]
        times, states = [], []
        for p in points:
            P, V, A = p.positions, p.velocities, p.accelerations
            pos = [0.0 if i is None else P[i] for i in cols]
            vel = [0.0 if i is None else V[i] for i in cols] if V else None
            acc = [0.0 if i is None else A[i] for i in cols] if A else None
            times.append(p.time_from_start)
            states.append(State(pos, vel, acc))
        prepared = PreparedTrajectory(times, states)
        prepared.joint_names = list(joint_names)
        return prepared

    def _build(self, joint_names, points, start, now, prepared=None):
        if (prepared is None or prepared.joint_names != list(joint_names)
                or len(prepared.times) != len(points)):
            prepared = self.prepare(joint_names, points)
        index = {j: i for i, j in enumerate(joint_names)}
        cur_pos, cur_vel, cur_acc = self._current_desired(now)
        # continuous joints: shift the whole joint trajectory by 2*pi*k so that it starts the short
        # way; joints the goal does not name hold their current desired position
        offsets = [0.0] * self.n
        for c, j in enumerate(self.joints):
            if j.name not in index:
                offsets[c] = cur_pos[c]
            elif j.type == "continuous":
                first = points[0].positions[index[j.name]]
                offsets[c] = cur_pos[c] + angles.shortest_angular_distance(cur_pos[c], first) - first
        placed = prepared.activate(start, now, State(cur_pos, cur_vel, cur_acc), offsets)
        if placed is None:  # every point is in the past but the last is 'now': jump to it
            last = prepared.states[-1]
            return Trajectory(now, State([p + o for p, o in zip(last.positions, offsets)]), [])
        return placed

    # -- loop ------------------------------------------------------------------------------
    def update(self, t, dt):
        self._now = t
        if self.trajectory is None:
            self._hold(t)
        dpos, dvel, dacc = self.trajectory.sample(t)
        self._desired = (dpos, dvel, dacc)
        if self.acts:           # the piece that holds at t first: the errors are the actuators'
            self._write_actuators()
            epos, evel = self._errors(t, dpos, dvel)
        else:
            epos, evel = self._errors(t, dpos, dvel)
            self._write(dpos, dvel, epos, evel, dt)
        if self.goal is not None:
            self._check_goal(t, epos, evel)
        self._watch_path(t)
        self._samples(t, dpos, dvel, dacc, epos, evel)

    def _samples_due_from(self):
        """The time from which an update leaves a state sample or action feedback."""
        due = INF if self._next_state is None else self._next_state - 1e-9
        if self.goal is not None and not self._feedback_with_state:
            due = min(due, -INF if self._next_feedback is None else self._next_feedback - 1e-9)
        return due

    def _goal_due(self, t):
        """The time from which an update has the goal to check: from the trajectory's end on
        (until its outcome); before it, for path tolerances, at every update unless the joints'
        actuators watch them (_watch_path: then at the step at which one is exceeded, where the
        World ends its native stretch), else never."""
        g = self.goal
        if g is None:
            return INF
        if t >= g.end_time:
            return t
        if g.checks_path and self._path_watched is not g:
            return t
        return g.end_time

    #: the goal whose path tolerances the joints' actuators watch (None: none)
    _path_watched = None

    def _watch_path(self, t):
        """The active goal's path tolerances to the joints' actuators as bands while they apply
        (a goal before its trajectory's end, with path tolerances), else no bands."""
        g = self.goal
        if not (self.acts and g is not None and g.checks_path and t < g.end_time):
            g = None
        if g is self._path_watched:
            return
        for k, a in enumerate(self.acts):
            if g is None:
                a.unwatch_band()
            else:
                a.watch_band(g.path[k].position, g.path[k].velocity)
        self._path_watched = g

    def _state_due(self, t):
        return self._next_state is None or t >= self._next_state - 1e-9

    @property
    def _feedback_with_state(self):
        """The action feedback is taken at state sample times (see _samples): unless the feedback
        is asked for more often than the state."""
        return self.action_monitor_rate <= self.state_publish_rate

    def _samples(self, t, dpos, dvel, dacc, epos, evel):
        state_due = self._state_due(t)
        if state_due:
            self._next_state = (self._next_state or t) + 1.0 / self.state_publish_rate
            if self._next_state < t:
                self._next_state = t + 1.0 / self.state_publish_rate
            apos, avel = self._actual()
            self.pending = dict(stamp=t, joint_names=list(self.joint_names), desired=(dpos, dvel, dacc),
                                actual=(apos, avel), error=(epos, evel))
        # ros_controllers sends the action feedback from a timer of action_monitor_rate (simulated
        # time) beside the control loop, with the last update's sample, so its phase against the
        # updates is arbitrary. Here it is taken at the first state sample once its period has
        # passed, on a schedule kept from the goal's first feedback (at 50 and 20 Hz: 60 and 40 ms
        # apart in turn, 20 Hz on average): a feedback between two state samples would end a batch
        # of native steps of its own (a Python update), a fifth more of them in a motion.
        if self.goal is None or (self._feedback_with_state and not state_due):
            return
        if self._next_feedback is None or t >= self._next_feedback - 1e-9:
            period = 1.0 / self.action_monitor_rate
            if self._feedback_with_state:
                # a schedule older than one period is a previous goal's: this goal's starts now
                nxt = (self._next_feedback or t) + period
                self._next_feedback = nxt if nxt > t else t + period
            else:
                self._next_feedback = t + period
            apos, avel = self._actual()
            self.pending_feedback = (self.goal.goal_id, dict(stamp=t, joint_names=list(self.joint_names),
                                                             desired=(dpos, dvel, dacc), actual=(apos, avel),
                                                             error=(epos, evel)))

    def _check_goal(self, t, epos, evel):
        g = self.goal
        if t < g.end_time:
            for i, tol in enumerate(g.path):
                if tol.position > 0.0 and abs(epos[i]) > tol.position:
                    self._abort(t, PATH_TOLERANCE_VIOLATED,
                                "path tolerance violated: joint '%s' is %.4g from the desired position "
                                "(tolerance %.4g) at t=%.3f s" % (self.joint_names[i], epos[i],
                                                                  tol.position, t))
                    return
                if tol.velocity > 0.0 and abs(evel[i]) > tol.velocity:
                    self._abort(t, PATH_TOLERANCE_VIOLATED,
                                "path tolerance violated: joint '%s' velocity error %.4g (tolerance %.4g)"
                                % (self.joint_names[i], evel[i], tol.velocity))
                    return
            return
        bad = None
        for i, tol in enumerate(g.goal):
            if tol.position > 0.0 and abs(epos[i]) > tol.position:
                bad = "joint '%s' is %.4g from its goal position (tolerance %.4g)" % (
                    self.joint_names[i], epos[i], tol.position)
                break
            if tol.velocity > 0.0 and abs(evel[i]) > tol.velocity:
                bad = "joint '%s' still moves at %.4g (stopped velocity tolerance %.4g)" % (
                    self.joint_names[i], -evel[i], tol.velocity)
                break
        if bad is None:
            self.events.append((g.goal_id, "succeeded", SUCCESSFUL, ""))
            self.goal = None
        elif t >= g.end_time + g.goal_time:
            self._abort(t, GOAL_TOLERANCE_VIOLATED, "goal tolerance violated %.3f s after the "
                                                    "trajectory's end: %s"
                        % (t - g.end_time, bad))

    def _abort(self, t, code, text):
        self.events.append((self.goal.goal_id, "aborted", code, text))
        self.goal = None
        self._hold(t)

    def _write(self, dpos, dvel, epos, evel, dt):
        """The joints' commands from the desired state and the errors (no actuators)."""
        raise NotImplementedError

    def _write_actuators(self):
        """The joints' actuators: the piece of the trajectory that holds now."""
        self._place_piece(self._now)

    # -- the joints' actuators: the piece of the trajectory that holds, at every step ------------
    #: what the joints' actuators drive (actuators.OUT_*): the trajectory's pieces are placed in
    #: them (SEGMENT_PID) where every joint can take that output (JointResource.can_drive)
    OUTPUT = actuators.OUT_EFFORT
    acts = ()
    #: the pieces placed at once: the one that holds and those queued behind it, which take over in
    #: turn without an update (Actuator.set_pieces)
    PIECES = actuators.MAX_QUEUE + 1
    _placed = None      # (trajectory, time, [Piece]) placed in the actuators

    def _take_joints(self, gains):
        """The joints' actuators (SEGMENT_PID with OUTPUT; ``gains`` per joint or None), or none
        (``acts`` empty: the controller writes the joints' commands at every update)."""
        self.acts = []
        self._placed = None
        self._path_watched = None
        if not all(j.can_drive(self.OUTPUT) for j in self.joints):
            return
        for k, j in enumerate(self.joints):
            a = j.actuate(actuators.SEGMENT_PID, None if gains is None else gains[k], self._error_rule(j),
                          owner=self, output=self.OUTPUT)
            a.unwatch_band()
            a.hold(j.position)          # until the first update places the trajectory
            self.acts.append(a)

    def _release_joints(self):
        for j, a in zip(self.joints, self.acts):
            if j.owner is self:
                a.unwatch_band()
                if j.interface == self.INTERFACE:   # the hardware keeps the last command
                    j.command = a.last.output
                j.release()
        self.acts = []
        self._path_watched = None

    def _place_piece(self, t):
        """The piece of the trajectory that holds at ``t`` and those after it into the actuators,
        unless the pieces placed hold it with more than half of them still to come (or end in the
        final hold): an update at a state sample tops the queue up before it runs dry."""
        placed = self._placed
        if placed is not None and placed[0] is self.trajectory and t >= placed[1]:
            pieces = placed[2]
            k = _holding(pieces, t)
            if k is not None and (len(pieces) - k > self.PIECES // 2 or pieces[-1].kind == HOLD):
                return
        pieces = self.trajectory.pieces(t, self.PIECES)
        self._placed = (self.trajectory, t, pieces)
        for k, a in enumerate(self.acts):
            a.set_pieces([_actuator_piece(p, k) for p in pieces])

    def _piece_due(self, t, dt):
        """The next update the actuated controller needs: the end of the last piece placed, a state
        sample or feedback, a goal check (t: now, when no piece is placed)."""
        placed = self._placed
        if self.trajectory is None or placed is None or placed[0] is not self.trajectory:
            return t
        last = placed[2][-1]
        ends = min(last.abs_until, last.base + last.rel_until if last.rel_until < INF else INF)
        # a step starting at or after `ends` needs the next piece; the float comparisons of the
        # piece's own test decide exactly, so the update is asked for half a step early
        return min(ends - 0.5 * dt, self._samples_due_from(), self._goal_due(t))


def _holding(pieces, t):
    """The index of the first of ``pieces`` that holds for a step starting at ``t`` (the actuators
    pass over the others: actuators.piece_at), or None."""
    for k, p in enumerate(pieces):
        if t < p.abs_until and t - p.base < p.rel_until:
            return k
    return None


def _actuator_piece(piece, k):
    """Joint ``k``'s actuator piece of the trajectory's ``piece``."""
    if piece.kind == HOLD:
        return actuators.hold_piece(piece.positions[k])
    seg = piece.segment
    if piece.kind == ABSOLUTE:
        return actuators.segment_piece(seg.coeffs[k], seg.t0, seg.t1, until=piece.abs_until)
    off = piece.offsets
    return actuators.segment_piece(seg.coeffs[k], seg.t0, seg.t1, base=piece.base,
                                   offset=None if off is None else off[k], until=piece.abs_until,
                                   rel_until=piece.rel_until)


class PositionJointTrajectoryController(JointTrajectoryControllerBase):
    """The joints' actuators set them kinematically to the trajectory's desired positions at
    every step (OUT_POSITION: as the hardware's position write, saturated by the velocity limits);
    an update places the next piece when the last one ends."""
    TYPE = "position_controllers/JointTrajectoryController"
    INTERFACE = POSITION
    OUTPUT = actuators.OUT_POSITION

    def _reset_pids(self):
        self._take_joints(None)

    def stopping(self, t):
        super(PositionJointTrajectoryController, self).stopping(t)
        self._release_joints()

    def _write(self, dpos, dvel, epos, evel, dt):
        for j, p in zip(self.joints, dpos):
            j.command = p

    def update_due(self, t, iteration, dt):
        return self._piece_due(t, dt) if self.acts else t


class _ClosedLoopTrajectoryController(JointTrajectoryControllerBase):
    """ros_controllers' ClosedLoopHardwareInterfaceAdapter: per joint, command =
    velocity_ff * desired velocity + PID(position error, velocity error); an effort or a velocity
    depending on the interface.

    The PIDs run in the joints' actuators (SEGMENT_PID with the interface's OUTPUT: the piece of
    the trajectory that holds, at every step, natively); an update places the next piece when the
    last one ends (JointTrajectoryControllerBase._take_joints). A joint whose interface the
    actuator cannot drive (a velocity joint with the
    hardware's own pid_gains PID after the controller's) makes the controller run its PIDs in
    Python at every update instead, writing the joints' commands."""
    OUTPUT = actuators.OUT_EFFORT

    def __init__(self, name, hw, params):
        super(_ClosedLoopTrajectoryController, self).__init__(name, hw, params)
        gains = params.child("gains", required=True)
        ff = params.child("velocity_ff")
        #: the gains per joint (dynamic_reconfigure swaps them)
        self.pids = [Pid(PidGains.from_params(gains.child(j, required=True))) for j in self.joint_names]
        self.pid_namespaces = [gains.path(j) for j in self.joint_names]
        self.velocity_ff = [ff.get(j, 0.0, kind=float) for j in self.joint_names]
        self._gains = []

    def _reset_pids(self):
        for p in self.pids:
            p.reset()
        self._take_joints([p.gains for p in self.pids])
        for a, ff in zip(self.acts, self.velocity_ff):
            a.feedforward = ff
        self._gains = [p.gains for p in self.pids]

    def stopping(self, t):
        super(_ClosedLoopTrajectoryController, self).stopping(t)
        self._release_joints()

    def _write(self, dpos, dvel, epos, evel, dt):
        for j, pid, ff, ep, ev, v in zip(self.joints, self.pids, self.velocity_ff, epos, evel, dvel):
            j.command = pid.compute(ep, dt, ev) + ff * v

    def _write_actuators(self):
        for k, (a, pid) in enumerate(zip(self.acts, self.pids)):
            if pid.gains is not self._gains[k]:
                self._gains[k] = a.gains = pid.gains
        super(_ClosedLoopTrajectoryController, self)._write_actuators()

    def update_due(self, t, iteration, dt):
        if not self.acts:
            return t
        if any(p.gains is not g for p, g in zip(self.pids, self._gains)):
            return t
        return self._piece_due(t, dt)


class EffortJointTrajectoryController(_ClosedLoopTrajectoryController):
    TYPE = "effort_controllers/JointTrajectoryController"
    INTERFACE = EFFORT


class VelocityJointTrajectoryController(_ClosedLoopTrajectoryController):
    """The PIDs' outputs are the velocity joints' motor velocities (OUT_VELOCITY actuators)."""
    TYPE = "velocity_controllers/JointTrajectoryController"
    INTERFACE = VELOCITY
    OUTPUT = actuators.OUT_VELOCITY
