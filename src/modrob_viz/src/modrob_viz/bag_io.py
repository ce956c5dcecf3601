"""Trajectories to and from rosbag files (no rospy in this module; rosbag itself needs no master).

3D points are ``geometry_msgs/PointStamped`` messages, one per point, on ``POINTS_TOPIC``.
Joint trajectories are stored point by point: for every recorded trajectory one
``trajectory_msgs/JointTrajectory`` with its joint names and no points on ``JOINT_NAMES_TOPIC``,
then each ``JointTrajectoryPoint`` on ``JOINT_POINTS_TOPIC``. A bag made with
``rosbag record /tp_rv_topic`` (whole ``JointTrajectory`` messages) is read as well.
"""
import os

import genpy
import rosbag
from geometry_msgs.msg import PointStamped
from trajectory_msgs.msg import JointTrajectory

from modrob_viz.errors import BagError
from modrob_viz.joint_path import JointPath

POINTS_TOPIC = "/trajectory_3d/points"
JOINT_NAMES_TOPIC = "/joint_trajectory/joint_names"
JOINT_POINTS_TOPIC = "/joint_trajectory/points"
TRAJECTORY_TOPIC = "/tp_rv_topic"


def _open(path, mode):
    path = os.path.expanduser(path or "")
    if not path:
        raise BagError("no bag file given: set the ~bag_file parameter")
    if mode == "r" and not os.path.isfile(path):
        raise BagError("bag file '%s' does not exist (yet)" % path, waiting=True)
    if mode in ("w", "a"):
        folder = os.path.dirname(os.path.abspath(path))
        if not os.path.isdir(folder):
            try:
                os.makedirs(folder)
            except OSError as err:
                raise BagError("cannot create folder '%s' for bag '%s': %s" % (folder, path, err))
        if mode == "a" and not os.path.isfile(path):
            mode = "w"
    try:
        return rosbag.Bag(path, mode)
    except rosbag.ROSBagUnindexedException:
        raise BagError("bag '%s' is unindexed: it is being written, or its writer died (then run "
                       "'rosbag reindex %s')" % (path, path), waiting=True)
    except (rosbag.ROSBagException, OSError, ValueError) as err:
        raise BagError("cannot open bag '%s' (%s): %s" % (path, "read" if mode == "r" else "write", err))


def _topics(bag):
    return sorted(bag.get_type_and_topic_info().topics)


def _stamp(i, start=1.0, dt=0.001):
    return genpy.Time.from_sec(start + i * dt)


def write_points(path, points, frame_id, topic=POINTS_TOPIC, stamps=None, mode="w"):
    """Write (x, y, z) points as PointStamped messages; returns how many were written."""
    bag = _open(path, mode)
    try:
        for i, p in enumerate(points):
            msg = PointStamped()
            msg.header.seq = i
            msg.header.frame_id = frame_id
            msg.header.stamp = stamps[i] if stamps is not None else _stamp(i)
            msg.point.x, msg.point.y, msg.point.z = (float(v) for v in p)
            bag.write(topic, msg, msg.header.stamp)
    finally:
        bag.close()
    return len(points)


def read_points(path, topic=POINTS_TOPIC):
    """(points, frame_id) from a bag of PointStamped (or Point / PoseStamped) messages."""
    bag = _open(path, "r")
    try:
        topics = _topics(bag)
        if topic not in topics:
            raise BagError("bag '%s' has no topic '%s' (it has: %s); record one with "
                           "trajectory_3Dpoints_recorder or set ~bag_topic"
                           % (path, topic, ", ".join(topics) or "no topics"), waiting=not topics)
        points, frame_id = [], ""
        for _, msg, _ in bag.read_messages(topics=[topic]):
            if hasattr(msg, "point"):
                p, frame_id = msg.point, msg.header.frame_id or frame_id
            elif hasattr(msg, "pose"):
                p, frame_id = msg.pose.position, msg.header.frame_id or frame_id
            elif hasattr(msg, "x") and hasattr(msg, "z"):
                p = msg
            else:
                raise BagError("topic '%s' in bag '%s' holds %s messages, not points"
                               % (topic, path, msg._type))
            points.append((p.x, p.y, p.z))
    finally:
        bag.close()
    return points, frame_id


def append_joint_trajectory(path, trajectory, stamp=None):
    """Append one JointTrajectory, point by point; returns the number of points written."""
    bag = _open(path, "a")
    try:
        t = stamp or _stamp(0)
        header = JointTrajectory()
        header.header = trajectory.header
        header.joint_names = list(trajectory.joint_names)
        bag.write(JOINT_NAMES_TOPIC, header, t)
        for i, point in enumerate(trajectory.points):
            bag.write(JOINT_POINTS_TOPIC, point, t + genpy.Duration.from_sec(1e-6 * (i + 1)))
    finally:
        bag.close()
    return len(trajectory.points)


def read_joint_trajectory(path):
    """All joint points of a bag as one :class:`JointPath` (recorded trajectories are
    concatenated; they must name the same joints)."""
    bag = _open(path, "r")
    try:
        topics = _topics(bag)
        if JOINT_POINTS_TOPIC in topics:
            names, points = None, []
            for topic, msg, _ in bag.read_messages(topics=[JOINT_NAMES_TOPIC, JOINT_POINTS_TOPIC]):
                if topic == JOINT_NAMES_TOPIC:
                    if names is not None and list(msg.joint_names) != names:
                        raise BagError("bag '%s' holds trajectories for different joints (%s, then %s)"
                                       % (path, ", ".join(names), ", ".join(msg.joint_names)))
                    names = list(msg.joint_names)
                else:
                    if names is None:
                        raise BagError("bag '%s' has joint points before any joint names on '%s'"
                                       % (path, JOINT_NAMES_TOPIC))
                    points.append(msg)
            return JointPath.from_points(names or [], points)
        candidates = [t for t, info in bag.get_type_and_topic_info().topics.items()
                      if info.msg_type == "trajectory_msgs/JointTrajectory"]
        if candidates:
            names, points = None, []
            for _, msg, _ in bag.read_messages(topics=sorted(candidates)):
                if names is not None and list(msg.joint_names) != names:
                    raise BagError("bag '%s' holds trajectories for different joints" % path)
                names = list(msg.joint_names)
                points.extend(msg.points)
            return JointPath.from_points(names or [], points)
        raise BagError("bag '%s' has no joint trajectory (no '%s' and no trajectory_msgs/JointTrajectory "
                       "topic; it has: %s); record one with joint_trajectory_recorder"
                       % (path, JOINT_POINTS_TOPIC, ", ".join(topics) or "no topics"), waiting=not topics)
    finally:
        bag.close()
