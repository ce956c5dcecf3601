"""Helpers shared by modrob_viz's rostest nodes: waiting for messages that satisfy a condition,
collecting /rosout, checking a node is alive, and driving the robot through joint_states."""
import threading

import rosnode
import rospy
import tf2_ros
from rosgraph_msgs.msg import Log
from sensor_msgs.msg import JointState


def wait_for(topic, msg_class, predicate=lambda m: True, timeout=30.0):
    """The first message on ``topic`` for which ``predicate`` holds, or None after ``timeout``."""
    found = []
    event = threading.Event()

    def callback(msg):
        if not event.is_set() and predicate(msg):
            found.append(msg)
            event.set()
    sub = rospy.Subscriber(topic, msg_class, callback, queue_size=50)
    event.wait(timeout)
    sub.unregister()
    return found[0] if found else None


class RosoutWatcher(object):
    """Collects /rosout (what every node logs); ``wait_for(node, level, text)`` returns the first
    matching message."""

    def __init__(self):
        self.messages = []
        self.lock = threading.Lock()
        self.sub = rospy.Subscriber("/rosout", Log, self._cb, queue_size=200)

    def _cb(self, msg):
        with self.lock:
            self.messages.append(msg)

    def wait_for(self, node, level, text, timeout=30.0):
        deadline = rospy.get_time() + timeout
        while rospy.get_time() < deadline and not rospy.is_shutdown():
            with self.lock:
                for m in self.messages:
                    if m.name == node and m.level >= level and text in m.msg:
                        return m
            rospy.sleep(0.1)
        return None


def alive(node):
    return rosnode.rosnode_ping(node, max_count=1)


class RobotDriver(object):
    """Publishes joint_states (so robot_state_publisher moves the model) and waits until tf shows
    the new configuration: ``move(names, q)`` returns the ee position from tf."""

    def __init__(self, base_frame="world", ee_frame="ee_link"):
        self.base_frame, self.ee_frame = base_frame, ee_frame
        self.pub = rospy.Publisher("joint_states", JointState, queue_size=10)
        self.buffer = tf2_ros.Buffer()
        self.listener = tf2_ros.TransformListener(self.buffer)
        self.names, self.q = None, None
        self.timer = rospy.Timer(rospy.Duration(0.05), self._republish)

    def _republish(self, _event=None):
        if self.names is not None:
            self._publish()

    def _publish(self):
        msg = JointState(name=list(self.names), position=list(self.q))
        msg.header.stamp = rospy.Time.now()
        self.pub.publish(msg)

    def move(self, names, q, timeout=20.0):
        self.names, self.q = list(names), list(q)
        start = rospy.Time.now()
        deadline = rospy.get_time() + timeout
        while rospy.get_time() < deadline and not rospy.is_shutdown():
            self._publish()
            try:
                t = self.buffer.lookup_transform(self.base_frame, self.ee_frame, rospy.Time(0))
                if t.header.stamp >= start:
                    return t
            except (tf2_ros.LookupException, tf2_ros.ConnectivityException, tf2_ros.ExtrapolationException):
                pass
            rospy.sleep(0.05)
        return None
