#!/usr/bin/env python3
"""rostest node: publish joint states for two_link_test.urdf and check the tf that
robot_state_publisher computes from them against a hand-computed transform."""
import math
import unittest

import rospy
import rostest
import tf2_ros
from sensor_msgs.msg import JointState


def expected_tool_position(q1, q2):
    """base_link -> tool0 by hand: up 0.1 (joint1 about z), up 0.3 (joint2 about y), 0.25 along x."""
    # In link1's frame after joint2 rotates about y by q2, link2's x axis is (cos q2, 0, -sin q2).
    local = (0.25 * math.cos(q2), 0.0, 0.4 - 0.25 * math.sin(q2))
    return (local[0] * math.cos(q1), local[0] * math.sin(q1), local[2])


class TfBetweenLinks(unittest.TestCase):
    def setUp(self):
        self.buffer = tf2_ros.Buffer()
        self.listener = tf2_ros.TransformListener(self.buffer)
        self.pub = rospy.Publisher("joint_states", JointState, queue_size=1)

    def lookup_when(self, q1, q2, timeout=20.0):
        """Publish the joint state until tf reports a transform stamped after we started."""
        start = rospy.Time.now()
        deadline = rospy.Time.now() + rospy.Duration(timeout)
        rate = rospy.Rate(20)
        while not rospy.is_shutdown() and rospy.Time.now() < deadline:
            msg = JointState(name=["joint1", "joint2"], position=[q1, q2])
            msg.header.stamp = rospy.Time.now()
            self.pub.publish(msg)
            try:
                t = self.buffer.lookup_transform("base_link", "tool0", rospy.Time(0))
                if t.header.stamp >= start:
                    return t.transform.translation
            except (tf2_ros.LookupException, tf2_ros.ExtrapolationException,
                    tf2_ros.ConnectivityException):
                pass
            rate.sleep()
        self.fail("no base_link -> tool0 transform from robot_state_publisher within %.0f s" % timeout)

    def test_tool_position_matches_hand_computation(self):
        for q1, q2 in [(0.0, 0.0), (math.pi / 2, 0.0), (0.7, -0.5)]:
            p = self.lookup_when(q1, q2)
            ex, ey, ez = expected_tool_position(q1, q2)
            self.assertAlmostEqual(p.x, ex, places=4, msg="x at q=(%g,%g)" % (q1, q2))
            self.assertAlmostEqual(p.y, ey, places=4, msg="y at q=(%g,%g)" % (q1, q2))
            self.assertAlmostEqual(p.z, ez, places=4, msg="z at q=(%g,%g)" % (q1, q2))


if __name__ == "__main__":
    rospy.init_node("tf_check")
    rostest.rosrun("modrob_description", "tf_between_links", TfBetweenLinks)
