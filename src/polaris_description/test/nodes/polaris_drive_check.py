#!/usr/bin/env python3
"""Checks for polaris_drive.test (see there)."""
import collections
import math
import unittest

import rospy
import rostest
import tf2_ros
from gazebo_msgs.msg import ModelStates
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import JointState


class PolarisDrive(unittest.TestCase):
    def wait_for(self, cond, timeout, what):
        end = rospy.Time.now() + rospy.Duration(timeout)
        while not rospy.is_shutdown() and not cond():
            if rospy.Time.now() > end:
                self.fail("timed out (%.0f s sim) waiting for %s" % (timeout, what))
            rospy.sleep(0.05)

    def test_drive_straight_and_odometry(self):
        odom = {}
        # model_states carries no stamp: keep each with the (simulated) time it arrived, so that
        # odometry is compared with the true pose of the same moment (at 1 m/s the newest two
        # messages of the two topics can be a tenth of a metre apart)
        states = collections.deque(maxlen=2000)
        rospy.Subscriber("/odom", Odometry, lambda m: odom.__setitem__("m", m))
        rospy.Subscriber("/gazebo/model_states", ModelStates,
                         lambda m: states.append((rospy.Time.now(), m)))
        pub = rospy.Publisher("/cmd_vel", Twist, queue_size=1)
        buf = tf2_ros.Buffer(rospy.Duration(60.0))
        self.listener = tf2_ros.TransformListener(buf)
        rospy.wait_for_message("/odom", Odometry, timeout=90)
        # the controllers are up when the joint states arrive
        rospy.wait_for_message("/joint_states", JointState, timeout=90)
        x0 = odom["m"].pose.pose.position.x
        t0 = rospy.Time.now()
        cmd = Twist()
        cmd.linear.x = 1.0
        while rospy.Time.now() - t0 < rospy.Duration(6.0):
            pub.publish(cmd)
            rospy.sleep(0.05)
        o = odom["m"]
        self.assertGreater(o.pose.pose.position.x - x0, 3.5, "the vehicle did not drive forward")
        self.assertAlmostEqual(o.twist.twist.linear.x, 1.0, delta=0.1)
        self.assertLess(abs(o.pose.pose.position.y), 0.1)
        stamp = o.header.stamp
        t, ms = min(list(states), key=lambda e: abs((e[0] - stamp).to_sec()))
        self.assertLess(abs((t - stamp).to_sec()), 0.05, "no model_states near the odometry's stamp")
        i = ms.name.index("polaris")
        p = ms.pose[i].position
        self.assertLess(math.hypot(p.x - o.pose.pose.position.x, p.y - o.pose.pose.position.y), 0.1)
        tr = buf.lookup_transform("odom", "base_link_polaris", o.header.stamp, rospy.Duration(10.0))
        self.assertAlmostEqual(tr.transform.translation.x, o.pose.pose.position.x, delta=0.01)
        # stale commands stop the vehicle (Ackermann node's timeout)
        t1 = rospy.Time.now()
        while rospy.Time.now() - t1 < rospy.Duration(4.0):
            rospy.sleep(0.05)
        self.assertLess(abs(odom["m"].twist.twist.linear.x), 0.05)


if __name__ == "__main__":
    rospy.init_node("polaris_drive_check")
    rostest.rosrun("polaris_description", "polaris_drive", PolarisDrive)
