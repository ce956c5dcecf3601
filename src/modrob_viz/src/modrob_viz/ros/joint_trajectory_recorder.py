"""joint_trajectory_recorder: trajectory_msgs/JointTrajectory on /tp_rv_topic -> a bag of
joint points (seed 000, section III-D)."""
import queue

import rospy
from std_msgs.msg import Int32
from trajectory_msgs.msg import JointTrajectory

from modrob_viz import bag_io
from modrob_viz.errors import VizError
from modrob_viz.joint_path import JointPath
from modrob_viz.ros.common import latched


class JointTrajectoryRecorder(object):
    """Every trajectory received on ``topic`` is checked and appended to ``bag_file`` point by
    point; ``~recorded_points`` (latched) counts the points in the bag. Bad trajectories
    (ragged points, NaN, no joint names) are refused with a reason and nothing is written."""

    def __init__(self, bag_file, topic="/tp_rv_topic", fresh=True):
        self.bag_file = bag_file
        self.count = 0
        self.inbox = queue.Queue()
        if not fresh:
            try:
                self.count = len(bag_io.read_joint_trajectory(bag_file))
            except VizError:
                self.count = 0
        else:
            bag_io.write_points(bag_file, [], "", topic=bag_io.JOINT_NAMES_TOPIC)  # truncate: a new bag
        self.count_pub = latched("~recorded_points", Int32)
        self.count_pub.publish(Int32(self.count))
        self.sub = rospy.Subscriber(topic, JointTrajectory, self.inbox.put, queue_size=10)
        rospy.loginfo("joint_trajectory_recorder: %s -> %s", rospy.resolve_name(topic), bag_file)

    def spin(self):
        while not rospy.is_shutdown():
            try:
                msg = self.inbox.get(timeout=0.2)
            except queue.Empty:
                continue
            self.record(msg)

    def record(self, msg):
        try:
            if not msg.joint_names:
                raise VizError("trajectory has no joint names")
            JointPath.from_points(msg.joint_names, msg.points)  # validates shape and finiteness
            n = bag_io.append_joint_trajectory(self.bag_file, msg)
        except VizError as err:
            rospy.logerr("joint_trajectory_recorder: trajectory refused, nothing written: %s", err)
            return
        self.count += n
        self.count_pub.publish(Int32(self.count))
        rospy.loginfo("joint_trajectory_recorder: recorded %d points (%s); %d in %s",
                      n, ", ".join(msg.joint_names), self.count, self.bag_file)
