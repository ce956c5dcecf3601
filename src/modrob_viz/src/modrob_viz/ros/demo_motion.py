"""Demo motion sources: ``demo_joint_motion`` (a joint-space wave on joint_states, so the tf-based
tools have something to trace) and ``tp_trajectory_publisher`` (a planner-like JointTrajectory
on /tp_rv_topic, as the seed's TP team sent)."""
import rospy
from sensor_msgs.msg import JointState
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

from modrob_viz import samples


class DemoJointMotion(object):
    """Publishes ``joint_states`` for every movable joint of ``tree`` at ``rate`` Hz."""

    def __init__(self, tree, rate=30.0, period=8.0, amplitude=0.5):
        self.tree = tree
        self.rate = rate
        self.period = period
        self.amplitude = amplitude
        self.pub = rospy.Publisher("joint_states", JointState, queue_size=10)

    def spin(self):
        rate = rospy.Rate(self.rate)
        start = rospy.get_time()
        while not rospy.is_shutdown():
            msg = JointState()
            msg.header.stamp = rospy.Time.now()
            msg.name = list(self.tree.joint_names)
            msg.position = samples.joint_wave(msg.name, self.tree.limits, rospy.get_time() - start,
                                              self.period, self.amplitude)
            self.pub.publish(msg)
            rate.sleep()


def trajectory_msg(path):
    msg = JointTrajectory()
    msg.header.stamp = rospy.Time.now()
    msg.joint_names = list(path.names)
    for row, t in zip(path.positions, path.times):
        p = JointTrajectoryPoint()
        p.positions = row.tolist()
        p.time_from_start = rospy.Duration.from_sec(float(t))
        msg.points.append(p)
    return msg


def publish_sample_trajectory(tree, topic="/tp_rv_topic", n=3700, duration=11.1, wait=10.0):
    """Publishes one sample trajectory of ``n`` points (latched) once a subscriber is there or
    after ``wait`` s; returns the message."""
    pub = rospy.Publisher(topic, JointTrajectory, queue_size=1, latch=True)
    deadline = rospy.get_time() + wait
    while pub.get_num_connections() == 0 and rospy.get_time() < deadline and not rospy.is_shutdown():
        rospy.sleep(0.1)
    msg = trajectory_msg(samples.sample_joint_trajectory(tree.joint_names, tree.limits, n, duration))
    pub.publish(msg)
    rospy.loginfo("tp_trajectory_publisher: published %d points for joints %s on %s", len(msg.points),
                  ", ".join(msg.joint_names), rospy.resolve_name(topic))
    return msg
