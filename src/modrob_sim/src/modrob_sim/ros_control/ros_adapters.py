"""ROS interfaces of the controllers (thin): topics, the follow_joint_trajectory action and the
PID reconfigure servers. Callbacks only store (commands go to the controller's lock-protected
buffer, goals to a queue); the simulation loop calls ``before_update`` (hand goals to the core)
and ``after_update`` (publish what the core produced)."""
import collections
import math
import threading
import time

import actionlib
import rospy
from control_msgs.msg import (FollowJointTrajectoryAction, FollowJointTrajectoryFeedback,
                              FollowJointTrajectoryResult, GripperCommandAction, GripperCommandResult,
                              JointControllerState, JointTrajectoryControllerState)
from control_msgs.srv import QueryTrajectoryState, QueryTrajectoryStateResponse
from geometry_msgs.msg import Quaternion, TransformStamped, Twist, TwistStamped
from nav_msgs.msg import Odometry
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64, Float64MultiArray
from tf2_msgs.msg import TFMessage
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

from modrob_sim.errors import ModrobError
from dynamic_reconfigure.server import Server as ReconfigureServer

from modrob_sim.gazebo_ros.action_servers import restamp_after_reset
from modrob_sim.gazebo_ros.native_pub import publisher
from modrob_sim.reconfigure_config import ConfigType, Param, shutdown_server
from modrob_sim.ros_control.controllers.joint_trajectory import TrajectoryPoint
from modrob_sim.ros_control.params import join
from modrob_sim.ros_control.ros_pid_reconfigure import PidReconfigure

THROTTLE = 5.0   # seconds between two warnings about the same bad command


def _stamp(t):
    return rospy.Time.from_sec(max(0.0, t))


class _Throttle(object):
    def __init__(self):
        self._last = {}

    def warn(self, key, text):
        wall = time.monotonic()
        last = self._last.get(key)
        if last is None or wall - last >= THROTTLE:
            self._last[key] = wall
            rospy.logwarn(text)


def _status_in_sim_time(adapter):
    """actionlib publishes the status array from a rospy.Timer, which the node's clock wakes
    after every batch of steps and which ends when time moves backwards (reset_simulation):
    the node's timer in simulated time does it instead (gazebo_ros.sim_timers)."""
    server = adapter.server
    rospy_timer = getattr(server, "status_timer", None)
    if rospy_timer is None:         # status_frequency 0: no status array
        return
    every = getattr(getattr(adapter.plugin, "context", None), "every", None)
    timer = every and every(1.0 / server.status_frequency, server.publish_status_async,
                            server.ns + "/status")
    if timer is not None:
        rospy_timer.shutdown()
        adapter.handles.append(timer)


def _wake(plugin):
    """The plugin's context.wake (a callback stored work: the update runs at the next step), or a
    no-op without a context."""
    context = getattr(plugin, "context", None)
    return context.wake if context is not None else (lambda: None)


class Adapter(object):
    def __init__(self, plugin, controller):
        self.plugin = plugin
        self.c = controller
        self.ns = join(plugin.namespace, controller.name)
        self.handles = []
        self.wake = _wake(plugin)
        buf = getattr(controller, "command", None)
        if buf is not None and hasattr(buf, "on_write"):
            buf.on_write = self.wake        # a new command: the controller's next update at once

    def waiting(self):
        """True when a callback stored work that the next update must take (goals, commands)."""
        return False

    def before_update(self, t):
        pass

    def after_update(self, t):
        pass

    def action_servers(self):
        """The adapter's actionlib servers (its ``server``, if any)."""
        server = getattr(self, "server", None)
        return [] if server is None else [server]

    def reset(self, t):
        """reset_simulation / reset_world (``t``: the simulated time after it; loop thread): the
        action servers order goals from ``t`` on (gazebo_ros.action_servers)."""
        for server in self.action_servers():
            restamp_after_reset(server, t)

    def shutdown(self):
        for h in self.handles:
            try:
                h.shutdown() if hasattr(h, "shutdown") else h.unregister()
            except Exception as exc:  # noqa: B902 - shutdown must go on for the other handles
                rospy.logdebug("shutting down %s: %s" % (h, exc))
        self.handles = []


class JointStateAdapter(Adapter):
    def __init__(self, plugin, controller):
        super(JointStateAdapter, self).__init__(plugin, controller)
        self.pub = publisher(join(plugin.namespace, "joint_states"), JointState, queue_size=10)
        self.handles.append(self.pub)

    def after_update(self, t):
        data, self.c.pending = self.c.pending, None
        if data is None:
            return
        stamp, names, pos, vel, eff = data
        msg = JointState(name=names, position=pos, velocity=vel, effort=eff)
        msg.header.stamp = _stamp(stamp)
        self.pub.publish(msg)


class SingleJointAdapter(Adapter):
    """``command`` (std_msgs/Float64); with a PID also ``state`` (JointControllerState) and the
    reconfigure server at ``<controller>/pid``."""

    def __init__(self, plugin, controller):
        super(SingleJointAdapter, self).__init__(plugin, controller)
        self.throttle = _Throttle()
        self.handles.append(rospy.Subscriber(self.ns + "/command", Float64, self._on_command, queue_size=10))
        self.state_pub = None
        if hasattr(controller, "pid"):
            self.state_pub = publisher(self.ns + "/state", JointControllerState, queue_size=10)
            self.handles.append(self.state_pub)
            # nobody listens: no update is made in Python for the state message
            controller.state_wanted = lambda: self.state_pub.get_num_connections() > 0
            self.handles.append(PidReconfigure(controller.pid, controller.pid_namespace,
                                               on_change=self._gains_changed))

    def _gains_changed(self, gains):
        rospy.loginfo("%s: new PID gains %s" % (self.ns, gains))
        self.wake()

    def _on_command(self, msg):
        res = self.c.set_command(msg.data)
        if not res.accepted:
            self.throttle.warn("nan", "%s/command: %s (the controller keeps its last command)"
                               % (self.ns, res.reason))
        elif res.clamped_from is not None:
            self.throttle.warn("clamp", "%s/command: %g is %s: clamped to %g"
                               % (self.ns, res.clamped_from, res.reason, res.value))

    def after_update(self, t):
        data, self.c.pending = self.c.pending, None
        # nobody listens: nothing would be sent, so the message is not built either (6 joints at
        # 100 Hz of simulated time were a few percent of the node's CPU)
        if data is None or self.state_pub is None or self.state_pub.get_num_connections() == 0:
            return
        msg = JointControllerState(set_point=data["set_point"], process_value=data["process_value"],
                                   process_value_dot=data["process_value_dot"], error=data["error"],
                                   time_step=data["time_step"], command=data["command"], p=data["p"],
                                   i=data["i"], d=data["d"], i_clamp=data["i_clamp"],
                                   antiwindup=data["antiwindup"])
        msg.header.stamp = _stamp(data["stamp"])
        self.state_pub.publish(msg)


class JointGroupAdapter(Adapter):
    """``command`` (std_msgs/Float64MultiArray, one value per joint in the ``joints`` order); with
    PIDs (effort_controllers/JointGroupPositionController) a reconfigure server at each
    ``<controller>/<joint>/pid``."""

    def __init__(self, plugin, controller):
        super(JointGroupAdapter, self).__init__(plugin, controller)
        self.throttle = _Throttle()
        self.handles.append(rospy.Subscriber(self.ns + "/command", Float64MultiArray, self._on_command,
                                             queue_size=1))
        for pid, ns in zip(getattr(controller, "pids", []), getattr(controller, "pid_namespaces", [])):
            self.handles.append(PidReconfigure(pid, ns, on_change=lambda _g: self.wake()))

    def _on_command(self, msg):
        res = self.c.set_command(msg.data)
        if not res.accepted:
            self.throttle.warn("bad", "%s/command: %s (the controller keeps its last command)"
                               % (self.ns, res.reason))
        elif res.clamped_from is not None:
            self.throttle.warn("clamp", "%s/command: clamped: %s" % (self.ns, res.reason))


class GripperActionAdapter(Adapter):
    """``gripper_cmd`` (control_msgs/GripperCommand action); for the effort type a reconfigure
    server at ``gains/<joint>``. Goals and cancels are queued and handed to the controller in the
    loop; outcomes are sent after the update that decided them."""

    def __init__(self, plugin, controller):
        super(GripperActionAdapter, self).__init__(plugin, controller)
        self.lock = threading.Lock()
        self.inbox = collections.deque()
        self.goals = {}
        self.server = actionlib.ActionServer(self.ns + "/gripper_cmd", GripperCommandAction,
                                             self._on_goal, self._on_cancel, auto_start=False)
        self.server.start()
        _status_in_sim_time(self)
        if getattr(controller, "pid", None) is not None:
            self.handles.append(PidReconfigure(controller.pid, controller.pid_namespace,
                                               on_change=lambda _g: self.wake()))

    def _on_goal(self, gh):
        with self.lock:
            self.inbox.append(("goal", gh))
        self.wake()

    def _on_cancel(self, gh):
        with self.lock:
            self.inbox.append(("cancel", gh))
        self.wake()

    def waiting(self):
        return bool(self.inbox)

    def before_update(self, t):
        with self.lock:
            items = list(self.inbox)
            self.inbox.clear()
        for kind, gh in items:
            gid = gh.get_goal_id().id
            if kind == "cancel":
                if not self.c.cancel(gid, t) and gid in self.goals:
                    self.goals.pop(gid).set_canceled(text="canceled before it became active")
                continue
            cmd = gh.get_goal().command
            ok, text = self.c.submit(gid, cmd.position, cmd.max_effort, t)
            if not ok:
                rospy.logerr("%s/gripper_cmd: goal rejected: %s" % (self.ns, text))
                gh.set_rejected(GripperCommandResult(position=self.c.joint.position), text)
                continue
            for note in self.c.notes(cmd.position, cmd.max_effort):
                rospy.logwarn("%s/gripper_cmd: %s" % (self.ns, note))
            gh.set_accepted("accepted by %s" % self.c.name)
            self.goals[gid] = gh

    def after_update(self, t):
        for gid, outcome, result, text in self.c.events:
            gh = self.goals.pop(gid, None)
            if gh is None:
                continue
            msg = GripperCommandResult(**result)
            if outcome == "succeeded":
                gh.set_succeeded(msg, text)
            elif outcome == "aborted":
                rospy.loginfo("%s: goal aborted: %s" % (self.ns, text))
                gh.set_aborted(msg, text)
            else:
                gh.set_canceled(msg, text)
        del self.c.events[:]

    def shutdown(self):
        for gh in self.goals.values():
            gh.set_aborted(GripperCommandResult(), "controller unloaded")
        self.goals = {}
        self.server.stop()
        super(GripperActionAdapter, self).shutdown()


#: trajectories from this many points on are announced (their segments take a second or more)
LONG_TRAJECTORY = 10000


def _point(pos, vel, acc=None):
    p = JointTrajectoryPoint(positions=list(pos), velocities=list(vel))
    if acc is not None:
        p.accelerations = list(acc)
    return p


def _points_from_msg(points):
    return [TrajectoryPoint(p.positions, p.velocities, p.accelerations,
                            p.time_from_start.to_sec()) for p in points]


class TrajectoryAdapter(Adapter):
    """``command`` (trajectory_msgs/JointTrajectory), ``state`` (JointTrajectoryControllerState),
    ``follow_joint_trajectory`` (control_msgs/FollowJointTrajectory action), ``query_state``.
    Goals, commands and cancels wait in ``inbox`` for the next update (``waiting``)."""

    def __init__(self, plugin, controller):
        super(TrajectoryAdapter, self).__init__(plugin, controller)
        self.lock = threading.Lock()
        self.inbox = collections.deque()
        self.goals = {}
        self.state_pub = publisher(self.ns + "/state", JointTrajectoryControllerState, queue_size=10)
        self.handles.append(self.state_pub)
        self.handles.append(rospy.Subscriber(self.ns + "/command", JointTrajectory, self._on_command,
                                             queue_size=10))
        self.handles.append(rospy.Service(self.ns + "/query_state", QueryTrajectoryState, self._on_query))
        self.server = actionlib.ActionServer(self.ns + "/follow_joint_trajectory",
                                             FollowJointTrajectoryAction,
                                             self._on_goal, self._on_cancel, auto_start=False)
        self.server.start()
        _status_in_sim_time(self)
        for name in ("pid_namespaces",):
            for pid, ns in zip(getattr(controller, "pids", []), getattr(controller, name, [])):
                self.handles.append(PidReconfigure(pid, ns, on_change=lambda _g: self.wake()))

    def waiting(self):
        return bool(self.inbox)

    # callbacks: parse, check and build every segment here, then hand the finished trajectory over:
    # the loop only places it in time (a 100k-point goal built in the loop thread blocked every
    # service of the node for about a second)
    def _parse(self, joint_names, msg_points):
        points = _points_from_msg(msg_points)
        check = self.c.check_points(joint_names, points)
        if not (check[0] and points):
            return points, check, None
        if len(points) >= LONG_TRAJECTORY:
            rospy.loginfo("%s: %d-point trajectory checked: building its segments off the simulation loop"
                          % (self.ns, len(points)))
        return points, check, self.c.prepare(joint_names, points)

    def _on_command(self, msg):
        parsed = self._parse(list(msg.joint_names), msg.points)
        with self.lock:
            self.inbox.append(("command", (msg,) + parsed))
        self.wake()

    def _on_goal(self, gh):
        traj = gh.get_goal().trajectory
        parsed = self._parse(list(traj.joint_names), traj.points)
        with self.lock:
            self.inbox.append(("goal", (gh,) + parsed))
        self.wake()

    def _on_cancel(self, gh):
        with self.lock:
            self.inbox.append(("cancel", gh))
        self.wake()

    def _on_query(self, req):
        """ros_controllers' queryStateService: the current trajectory sampled at ``req.time``
        (absolute, simulated time); fails while the controller is not running or for a time before
        the trajectory's start."""
        t = req.time.to_sec()

        def sample():       # in the loop thread: the trajectory and the joints belong to it
            c = self.c
            if c.state != "running":
                return ("Can't sample trajectory. Controller '%s' is not running (state: %s)"
                        % (c.name, c.state))
            traj = c.trajectory
            if traj is None or t < traj.start_time - 1e-9:
                return ("Requested sample time %.4f precedes trajectory start time %.4f"
                        % (t, t if traj is None else traj.start_time))
            return traj.sample(t)
        try:
            out = self.plugin.context.call(sample)
        except ModrobError as exc:
            raise rospy.ServiceException("%s/query_state: %s" % (self.ns, exc))
        if isinstance(out, str):
            rospy.logerr("%s/query_state: %s" % (self.ns, out))
            raise rospy.ServiceException(out)
        pos, vel, acc = out
        return QueryTrajectoryStateResponse(name=list(self.c.joint_names), position=pos, velocity=vel,
                                            acceleration=acc)

    # loop
    def before_update(self, t):
        with self.lock:
            items = list(self.inbox)
            self.inbox.clear()
        for kind, obj in items:
            if kind == "command":
                msg, points, (ok, code, text), prepared = obj
                if ok:
                    ok, code, text = self.c.submit(list(msg.joint_names), points, msg.header.stamp.to_sec(),
                                                   t, checked=True, prepared=prepared)
                if not ok:
                    rospy.logerr("%s/command rejected: %s" % (self.ns, text))
            elif kind == "goal":
                self._accept_or_reject(obj, t)
            elif kind == "cancel":
                gid = obj.get_goal_id().id
                if not self.c.cancel(gid, t) and gid in self.goals:
                    self.goals.pop(gid).set_canceled(text="canceled before it became active")

    def _accept_or_reject(self, item, t):
        gh, points, (ok, code, text), prepared = item
        goal = gh.get_goal()
        gid = gh.get_goal_id().id
        traj = goal.trajectory
        if ok:
            ok, code, text = self.c.submit(list(traj.joint_names), points,
                                           traj.header.stamp.to_sec(), t, goal_id=gid,
                                           path_tolerance=goal.path_tolerance,
                                           goal_tolerance=goal.goal_tolerance,
                                           goal_time_tolerance=goal.goal_time_tolerance.to_sec(),
                                           checked=True, prepared=prepared)
        if not ok:
            rospy.logerr("%s/follow_joint_trajectory: goal rejected: %s" % (self.ns, text))
            gh.set_rejected(FollowJointTrajectoryResult(error_code=code, error_string=text), text)
            return
        gh.set_accepted("accepted by %s" % self.c.name)
        self.goals[gid] = gh

    def after_update(self, t):
        for gid, outcome, code, text in self.c.events:
            gh = self.goals.pop(gid, None)
            if gh is None:
                continue
            result = FollowJointTrajectoryResult(error_code=code, error_string=text)
            if outcome == "succeeded":
                gh.set_succeeded(result, text)
            elif outcome == "aborted":
                rospy.logwarn("%s: goal aborted: %s" % (self.ns, text))
                gh.set_aborted(result, text)
            else:
                gh.set_canceled(result, text)
        del self.c.events[:]
        fb, self.c.pending_feedback = self.c.pending_feedback, None
        if fb is not None and fb[0] in self.goals:
            data = fb[1]
            msg = FollowJointTrajectoryFeedback(joint_names=data["joint_names"],
                                                desired=_point(*data["desired"]),
                                                actual=_point(*data["actual"]),
                                                error=_point(*data["error"]))
            msg.header.stamp = _stamp(data["stamp"])
            self.goals[fb[0]].publish_feedback(msg)
        data, self.c.pending = self.c.pending, None
        if data is not None and self.state_pub.get_num_connections() > 0:
            msg = JointTrajectoryControllerState(joint_names=data["joint_names"],
                                                 desired=_point(*data["desired"]),
                                                 actual=_point(*data["actual"]), error=_point(*data["error"]))
            msg.header.stamp = _stamp(data["stamp"])
            self.state_pub.publish(msg)

    def shutdown(self):
        for gh in self.goals.values():
            gh.set_aborted(FollowJointTrajectoryResult(error_code=-1, error_string="controller unloaded"),
                           "controller unloaded")
        self.goals = {}
        self.server.stop()
        super(TrajectoryAdapter, self).shutdown()


def diff_drive_config(c):
    """DiffDriveController.cfg's parameters (ranges as there, widened to hold the YAML's values:
    the server clamps what it reads from the parameter server, and Husky's separation multiplier
    is 1.875)."""
    def multiplier(name, value, text):
        return Param(name, "double", value, min(0.5, value), max(1.5, value), text)
    return ConfigType([
        multiplier("left_wheel_radius_multiplier", c.left_radius_multiplier,
                   "Left wheel radius multiplier."),
        multiplier("right_wheel_radius_multiplier", c.right_radius_multiplier,
                   "Right wheel radius multiplier."),
        multiplier("wheel_separation_multiplier", c.wheel_separation_multiplier,
                   "Wheel separation multiplier."),
        Param("publish_rate", "double", c.publish_rate, 0.0, max(2000.0, c.publish_rate),
              "Publish rate of odom."),
        Param("enable_odom_tf", "bool", c.enable_odom_tf, False, True, "Publish odom frame to tf."),
    ])


def _yaw_quaternion(yaw):
    return Quaternion(0.0, 0.0, math.sin(0.5 * yaw), math.cos(0.5 * yaw))


class MobileBaseAdapter(Adapter):
    """diff_drive_controller's and ackermann_steering_controller's topics: ``cmd_vel`` in
    (geometry_msgs/Twist), ``odom`` (nav_msgs/Odometry) and the odom -> base transform on /tf out
    at ``publish_rate``; with ``publish_cmd`` the limited command on ``cmd_vel_out``
    (TwistStamped), with ``publish_wheel_joint_controller_state`` the wheels on
    ``wheel_joint_controller_state`` (JointTrajectoryControllerState); both every update while
    someone subscribes."""

    def __init__(self, plugin, controller):
        super(MobileBaseAdapter, self).__init__(plugin, controller)
        self.throttle = _Throttle()
        self.odom_pub = publisher(self.ns + "/odom", Odometry, queue_size=100)
        self.tf_pub = publisher("/tf", TFMessage, queue_size=100)
        self.handles += [self.odom_pub, self.tf_pub]
        self.cmd_out_pub = self.wheel_pub = None
        if controller.publish_cmd:
            self.cmd_out_pub = publisher(self.ns + "/cmd_vel_out", TwistStamped, queue_size=100)
            self.handles.append(self.cmd_out_pub)
        if controller.publish_wheel_state:
            self.wheel_pub = publisher(self.ns + "/wheel_joint_controller_state",
                                       JointTrajectoryControllerState, queue_size=100)
            self.handles.append(self.wheel_pub)
        # nobody listens to either: the controller makes no update in Python for them
        per_update = [p for p in (self.cmd_out_pub, self.wheel_pub) if p is not None]
        controller.per_update_wanted = lambda: any(p.get_num_connections() > 0 for p in per_update)
        self.sub = rospy.Subscriber(self.ns + "/cmd_vel", Twist, self._on_cmd_vel, queue_size=1)
        self.handles.append(self.sub)
        self.reconfigure = None
        if hasattr(controller, "left_radius_multiplier"):
            self.reconfigure = ReconfigureServer(diff_drive_config(controller), self._on_reconfigure,
                                                 namespace=self.ns)

    def _on_reconfigure(self, config, level):
        """DiffDriveController's dynamic_reconfigure: each value a single reference the loop reads."""
        c = self.c
        c.left_radius_multiplier = config["left_wheel_radius_multiplier"]
        c.right_radius_multiplier = config["right_wheel_radius_multiplier"]
        c.wheel_separation_multiplier = config["wheel_separation_multiplier"]
        c.publish_rate = config["publish_rate"]
        c.enable_odom_tf = config["enable_odom_tf"]
        return config

    def shutdown(self):
        if self.reconfigure is not None:
            shutdown_server(self.reconfigure)
            self.reconfigure = None
        super(MobileBaseAdapter, self).shutdown()

    def _on_cmd_vel(self, msg):
        if self.c.state != "running":
            self.throttle.warn("stopped", "%s: Can't accept new commands. Controller is not running."
                               % self.ns)
            return
        if not self.c.allow_multiple_publishers and self.sub.get_num_connections() > 1:
            self.throttle.warn("many", "%s/cmd_vel: detected %d publishers; only 1 is allowed "
                               "(allow_multiple_cmd_vel_publishers: false): braking"
                               % (self.ns, self.sub.get_num_connections()))
            self.c.brake()
            return
        res = self.c.set_command(msg.linear.x, msg.angular.z)
        if not res.accepted:
            self.throttle.warn("nan", "%s/cmd_vel: %s" % (self.ns, res.reason))

    def after_update(self, t):
        c = self.c
        out, c.cmd_out = c.cmd_out, None
        if out is not None and self.cmd_out_pub is not None and self.cmd_out_pub.get_num_connections() > 0:
            msg = TwistStamped()
            msg.header.stamp = _stamp(out[0])
            msg.twist.linear.x, msg.twist.angular.z = out[1], out[2]
            self.cmd_out_pub.publish(msg)
        wheels, c.wheel_state = c.wheel_state, None
        if wheels is not None and self.wheel_pub is not None and self.wheel_pub.get_num_connections() > 0:
            self._publish_wheels(wheels)
        data, c.pending = c.pending, None
        if data is None:
            return
        stamp = _stamp(data["stamp"])
        q = _yaw_quaternion(data["heading"])
        odom = Odometry()
        odom.header.stamp = stamp
        odom.header.frame_id = c.odom_frame_id
        odom.child_frame_id = c.base_frame_id
        odom.pose.pose.position.x, odom.pose.pose.position.y = data["x"], data["y"]
        odom.pose.pose.orientation = q
        odom.pose.covariance = c.pose_covariance
        odom.twist.twist.linear.x, odom.twist.twist.angular.z = data["linear"], data["angular"]
        odom.twist.covariance = c.twist_covariance
        self.odom_pub.publish(odom)
        if c.enable_odom_tf:
            tf = TransformStamped()
            tf.header.stamp = stamp
            tf.header.frame_id = c.odom_frame_id
            tf.child_frame_id = c.base_frame_id
            tf.transform.translation.x, tf.transform.translation.y = data["x"], data["y"]
            tf.transform.rotation = q
            self.tf_pub.publish(TFMessage(transforms=[tf]))

    def _publish_wheels(self, w):
        joints = self.c.left + self.c.right
        actual = _point([j.position for j in joints], [j.velocity for j in joints])
        actual.effort = [j.effort for j in joints]
        desired = _point(w["positions"], w["velocities"], w["accelerations"])
        error = _point([d - j.position for d, j in zip(w["positions"], joints)],
                       [d - j.velocity for d, j in zip(w["velocities"], joints)])
        msg = JointTrajectoryControllerState(joint_names=list(self.c.joint_names), desired=desired,
                                             actual=actual, error=error)
        msg.header.stamp = _stamp(w["stamp"])
        self.wheel_pub.publish(msg)


def adapter_for(plugin, controller):
    from modrob_sim.ros_control.controllers.gripper_action import GripperActionControllerBase
    from modrob_sim.ros_control.controllers.joint_group import JointGroupControllerBase
    from modrob_sim.ros_control.controllers.joint_state import JointStateController
    from modrob_sim.ros_control.controllers.joint_trajectory import JointTrajectoryControllerBase
    from modrob_sim.ros_control.controllers.mobile_base import MobileBaseController
    from modrob_sim.ros_control.extensions import adapter_factory
    registered = adapter_factory(controller.TYPE)
    if registered is not None:
        return registered(plugin, controller)
    if isinstance(controller, JointStateController):
        return JointStateAdapter(plugin, controller)
    if isinstance(controller, MobileBaseController):
        return MobileBaseAdapter(plugin, controller)
    if isinstance(controller, JointTrajectoryControllerBase):
        return TrajectoryAdapter(plugin, controller)
    if isinstance(controller, JointGroupControllerBase):
        return JointGroupAdapter(plugin, controller)
    if isinstance(controller, GripperActionControllerBase):
        return GripperActionAdapter(plugin, controller)
    return SingleJointAdapter(plugin, controller)
