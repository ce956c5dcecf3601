"""geometry_msgs <-> the physics core's tuples, and simulated seconds -> rospy.Time."""
import math

import rospy
from geometry_msgs.msg import Pose, Twist

from modrob_sim.errors import RequestError
from modrob_sim.gazebo_ros import transforms as tf


def pose_from_msg(p, what):
    """((x, y, z), (qx, qy, qz, qw)) of a geometry_msgs/Pose, quaternion normalised (all zero =
    identity, as Gazebo); RequestError naming ``what`` for NaN or infinite values."""
    pose = ((p.position.x, p.position.y, p.position.z),
            (p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w))
    if not tf.is_finite(pose):
        raise RequestError("%s has a NaN or infinite value: %s" % (what, pose))
    return (pose[0], tf.quat_normalize(pose[1]))


def twist_from_msg(t, what):
    twist = ((t.linear.x, t.linear.y, t.linear.z), (t.angular.x, t.angular.y, t.angular.z))
    if not tf.is_finite(twist):
        raise RequestError("%s has a NaN or infinite value: %s" % (what, twist))
    return twist


def vector_from_msg(v):
    return (v.x, v.y, v.z)


def pose_to_msg(pose, msg=None):
    msg = msg or Pose()
    (msg.position.x, msg.position.y, msg.position.z) = pose[0]
    (msg.orientation.x, msg.orientation.y, msg.orientation.z, msg.orientation.w) = pose[1]
    return msg


def twist_to_msg(twist, msg=None):
    msg = msg or Twist()
    (msg.linear.x, msg.linear.y, msg.linear.z) = twist[0]
    (msg.angular.x, msg.angular.y, msg.angular.z) = twist[1]
    return msg


def ros_time(t):
    secs = int(math.floor(t))
    nsecs = int(round((t - secs) * 1e9))
    if nsecs >= 1000000000:
        secs, nsecs = secs + 1, nsecs - 1000000000
    return rospy.Time(secs, nsecs)
