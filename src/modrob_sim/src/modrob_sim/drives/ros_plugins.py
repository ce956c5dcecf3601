"""The ROS side of the gazebo_plugins drives: registers their file names with the /gazebo node and
wires the pure cores (diff_drive, skid_steer, planar_move, tricycle) to their topics.

Each drive subscribes to ``commandTopic`` (geometry_msgs/Twist, the latest command kept under the
plugin's lock), and at its update rate, in the step hook before the physics step (as Gazebo's
world-update-begin), publishes nav_msgs/Odometry on ``odometryTopic`` and the odometry transform
on /tf; topics are relative to the plugin's robotNamespace, frames take the namespace's
tf_prefix (tf::resolve).
"""
import threading

import rospy
from geometry_msgs.msg import TransformStamped, Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import JointState
from tf2_msgs.msg import TFMessage

from modrob_sim.gazebo_ros.plugin_base import ModelPlugin
from modrob_sim.gazebo_ros.plugins import register_plugin
from modrob_sim.sensors.ros_plugins import plugin_namespace, stamp, tf_prefix
from modrob_sim.sensors.sdf import join_ns, tf_resolve

from .common import POSE_COVARIANCE, diagonal, joint_transforms
from .diff_drive import DiffDrive
from .joint_states import JointStates
from .planar_move import PlanarMove
from .skid_steer import SkidSteer
from .tricycle import Tricycle

_WARNED = set()


def _warn_once(key, text):
    if key not in _WARNED:
        _WARNED.add(key)
        rospy.logwarn(text)


def transform(parent, child, pose, t):
    """A geometry_msgs/TransformStamped of ``child`` in ``parent`` at simulated time ``t``."""
    (p, q) = pose
    tr = TransformStamped()
    tr.header.stamp = stamp(t)
    tr.header.frame_id = parent
    tr.child_frame_id = child
    tr.transform.translation.x, tr.transform.translation.y, tr.transform.translation.z = p
    r = tr.transform.rotation
    r.x, r.y, r.z, r.w = q
    return tr


def odometry_message(reading, frame, child, t, pose_covariance, twist_covariance=None):
    """nav_msgs/Odometry from an Odom reading of modrob_sim.drives.common."""
    msg = Odometry()
    msg.header.stamp = stamp(t)
    msg.header.frame_id = frame
    msg.child_frame_id = child
    pp = msg.pose.pose
    pp.position.x, pp.position.y, pp.position.z = reading.position
    pp.orientation.x, pp.orientation.y, pp.orientation.z, pp.orientation.w = reading.orientation
    tw = msg.twist.twist
    tw.linear.x, tw.linear.y, tw.linear.z = reading.linear
    tw.angular.x, tw.angular.y, tw.angular.z = reading.angular
    msg.pose.covariance = pose_covariance
    if twist_covariance is not None:
        msg.twist.covariance = twist_covariance
    return msg


class DrivePlugin(ModelPlugin):
    """What every drive plugin does on the ROS side: the command subscriber, the odometry
    publisher and the /tf publisher. Subclasses make ``self.core`` in ``make_core`` and say
    which command fields they use (``command``)."""

    def load(self, model, spec, context):
        self.core = self.make_core()
        cfg = self.core.cfg
        self.ns = plugin_namespace(spec, context)
        prefix = tf_prefix(self.ns)
        self.odom_frame = tf_resolve(prefix, cfg.odometry_frame)
        self.base_frame = tf_resolve(prefix, cfg.robot_base_frame)
        self.prefix = prefix
        self._lock = threading.Lock()
        self._command = (0.0, 0.0)
        self.odom_pub = context.advertise(join_ns(self.ns, cfg.odometry_topic), Odometry, queue_size=1) \
            if self.publishes_odometry() else None
        self.tf_pub = context.advertise("/tf", TFMessage, queue_size=100)
        self.sub = rospy.Subscriber(join_ns(self.ns, cfg.command_topic), Twist, self._on_command,
                                    queue_size=1)
        rospy.loginfo("%s: %s -> wheels %s, odometry (%s) on %s, tf %s -> %s"
                      % (self.name, self.sub.name, ", ".join(j.name for j in self.core.joints),
                         cfg.odometry_source, self.odom_pub.name if self.odom_pub else "(none)",
                         self.odom_frame, self.base_frame))

    def publishes_odometry(self):
        return True

    def before_due(self):
        """The drive's update times (its core's ``next_due``)."""
        return self.core.next_due()

    def _on_command(self, msg):
        value = self.command(msg)
        with self._lock:
            self._command = value

    def command(self, msg):
        """The fields of a Twist the drive uses (stored; read in the loop thread)."""
        return (msg.linear.x, msg.angular.z)

    def latest_command(self):
        with self._lock:
            return self._command

    def publish_odometry(self, t, reading, pose_covariance, twist_covariance=None, with_tf=True):
        if self.odom_pub is not None:
            self.odom_pub.publish(odometry_message(reading, self.odom_frame, self.base_frame, t,
                                                   pose_covariance, twist_covariance))
        if with_tf:
            self.tf_pub.publish(TFMessage([transform(self.odom_frame, self.base_frame,
                                                     (reading.position, reading.orientation), t)]))

    def publish_joint_transforms(self, t, joints):
        """/tf of each joint's child link in its parent link (publishWheelTF)."""
        pre = self.prefix
        self.tf_pub.publish(TFMessage([transform(tf_resolve(pre, parent), tf_resolve(pre, child), pose, t)
                                       for parent, child, pose in joint_transforms(self.core.model, joints)]))

    def reset(self):
        with self._lock:
            self._command = (0.0, 0.0)
        self.core.reset()

    def shutdown(self):
        self.sub.unregister()
        for p in (self.odom_pub, self.tf_pub):
            if p is not None:
                p.unregister()


class DiffDrivePlugin(DrivePlugin):
    """libgazebo_ros_diff_drive.so."""

    def make_core(self):
        core = DiffDrive(self)
        if core.cfg.legacy_mode:
            _warn_once(("legacy", self.model.name),
                       "%s: <legacyMode> true is ignored, as Noetic's gazebo_ros_diff_drive ignores it "
                       "(the wheels are not swapped)" % self.name)
        return core

    def load(self, model, spec, context):
        DrivePlugin.load(self, model, spec, context)
        cfg = self.core.cfg
        self.joint_pub = context.advertise(join_ns(self.ns, "joint_states"), JointState, queue_size=1000) \
            if cfg.publish_wheel_joint_state else None
        self.pose_covariance = diagonal(POSE_COVARIANCE)

    def publishes_odometry(self):
        return self.core.cfg.publish_odom

    def before_step(self, t, dt):
        core = self.core
        if not core.update(t, dt, self.latest_command()):
            return
        cfg = core.cfg
        if cfg.publish_odom:
            self.publish_odometry(t, core.odometry(), self.pose_covariance, with_tf=cfg.publish_odom_tf)
        if cfg.publish_wheel_tf:
            self.publish_joint_transforms(t, core.joints)
        if self.joint_pub is not None:
            msg = JointState()
            msg.header.stamp = stamp(t)
            for name, position in core.wheel_positions():
                msg.name.append(name)
                msg.position.append(position)
            self.joint_pub.publish(msg)

    def shutdown(self):
        DrivePlugin.shutdown(self)
        if self.joint_pub is not None:
            self.joint_pub.unregister()


class SkidSteerPlugin(DrivePlugin):
    """libgazebo_ros_skid_steer_drive.so: odometry with the configured covariances on pose and
    twist; the odometry transform only with broadcastTF."""

    def make_core(self):
        return SkidSteer(self)

    def load(self, model, spec, context):
        DrivePlugin.load(self, model, spec, context)
        cx, cy, cyaw = self.core.cfg.covariance
        self.covariance = diagonal((cx, cy, 1e12, 1e12, 1e12, cyaw))

    def before_step(self, t, dt):
        if self.core.update(t, dt, self.latest_command()):
            self.publish_odometry(t, self.core.odometry(), self.covariance, self.covariance,
                                  with_tf=self.core.cfg.broadcast_tf)


class PlanarMovePlugin(DrivePlugin):
    """libgazebo_ros_planar_move.so: linear.x, linear.y and angular.z of cmd_vel move the model
    (its model actuator holds the velocity at every step); odometry and its transform at
    odometryRate. A new command wakes the loop, so it acts from the next step on."""

    def make_core(self):
        core = PlanarMove(self)
        if core.problem:
            _warn_once(("planar static", self.model.name), "%s: the base does not move: %s"
                       % (self.name, core.problem))
        return core

    def load(self, model, spec, context):
        DrivePlugin.load(self, model, spec, context)
        self._command = ((0.0, 0.0, 0.0), None)
        self._fresh = False
        self.pose_covariance = diagonal(POSE_COVARIANCE)

    def command(self, msg):
        return ((msg.linear.x, msg.linear.y, msg.angular.z), rospy.Time.now().to_sec())

    def _on_command(self, msg):
        value = self.command(msg)
        with self._lock:
            self._command = value
            self._fresh = True
        self.context.wake()

    def before_due(self):
        if self._fresh:
            return None
        return self.core.next_due()

    def before_step(self, t, dt):
        with self._lock:
            command, received = self._command
            self._fresh = False
        if self.core.update(t, dt, command, received):
            self.publish_odometry(t, self.core.odometry(), self.pose_covariance)

    def reset(self):
        DrivePlugin.reset(self)
        with self._lock:
            self._command = ((0.0, 0.0, 0.0), None)

    def shutdown(self):
        DrivePlugin.shutdown(self)
        self.core.shutdown()


class TricyclePlugin(DrivePlugin):
    """libgazebo_ros_tricycle_drive.so: linear.x is the driven wheel's speed, angular.z the
    steering angle."""

    def make_core(self):
        return Tricycle(self)

    def load(self, model, spec, context):
        DrivePlugin.load(self, model, spec, context)
        cfg = self.core.cfg
        self.joint_pub = context.advertise(join_ns(self.ns, "joint_states"), JointState, queue_size=1000) \
            if cfg.publish_wheel_joint_state else None
        self.pose_covariance = diagonal(POSE_COVARIANCE)

    def before_step(self, t, dt):
        core = self.core
        if not core.update(t, dt, self.latest_command()):
            return
        self.publish_odometry(t, core.odometry(), self.pose_covariance)
        if core.cfg.publish_wheel_tf:
            self.publish_joint_transforms(t, core.joints)
        if self.joint_pub is not None:
            msg = JointState()
            msg.header.stamp = stamp(t)
            for name, position, velocity in core.wheel_states():
                msg.name.append(name)
                msg.position.append(position)
                msg.velocity.append(velocity)
            self.joint_pub.publish(msg)

    def shutdown(self):
        DrivePlugin.shutdown(self)
        if self.joint_pub is not None:
            self.joint_pub.unregister()


class JointStatePublisherPlugin(ModelPlugin):
    """libgazebo_ros_joint_state_publisher.so -> sensor_msgs/JointState (name, position, velocity)
    on joint_states in its <robotNamespace>; without one, in the model's name (as the original),
    unless the model was spawned into a namespace."""

    def load(self, model, spec, context):
        self.core = JointStates(self)
        given = spec.element.find("robotNamespace") is not None and \
            (spec.element.find("robotNamespace").text or "").strip()
        ns = spec.robot_namespace if given or context.robot_namespace else model.name
        self.pub = context.advertise(join_ns(ns, "joint_states"), JointState, queue_size=1000)
        rospy.loginfo("%s: %s on %s"
                      % (self.name, ", ".join(j.name for j in self.core.joints), self.pub.name))

    def before_due(self):
        return self.core.gate.next_time

    def before_step(self, t, dt):
        states = self.core.update(t)
        if states is None or not self.pub.has_subscribers:
            return
        msg = JointState()
        msg.header.stamp = stamp(t)
        for name, position, velocity in states:
            msg.name.append(name)
            msg.position.append(position)
            msg.velocity.append(velocity)
        self.pub.publish(msg)

    def reset(self):
        self.core.reset()

    def shutdown(self):
        self.pub.unregister()


PLUGINS = {
    "libgazebo_ros_diff_drive.so": DiffDrivePlugin,
    "libgazebo_ros_skid_steer_drive.so": SkidSteerPlugin,
    "libgazebo_ros_joint_state_publisher.so": JointStatePublisherPlugin,
    "libgazebo_ros_planar_move.so": PlanarMovePlugin,
    "libgazebo_ros_tricycle_drive.so": TricyclePlugin,
}

for _name, _cls in PLUGINS.items():
    register_plugin(_name, _cls)
