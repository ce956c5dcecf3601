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

from modrob_sim.waits import command_publisher, wait_until


class PolarisDrive(unittest.TestCase):
    def test_drive_straight_and_odometry(self):
        odom = {}
        # odometry relays the vehicle's pose from /gazebo/model_states: each /odom pose must be
        # one of the poses the simulator published (model_states carries no stamp, and at
        # real_time_factor 0 a receipt time says little about the simulated time it was taken)
        states = collections.deque(maxlen=2000)
        rospy.Subscriber("/odom", Odometry, lambda m: odom.__setitem__("m", m))
        rospy.Subscriber("/gazebo/model_states", ModelStates,
                         lambda m: states.append(m))
        buf = tf2_ros.Buffer(rospy.Duration(60.0))
        self.listener = tf2_ros.TransformListener(buf)
        rospy.wait_for_message("/odom", Odometry, timeout=90)
        # the controllers are up when the joint states arrive
        rospy.wait_for_message("/joint_states", JointState, timeout=90)
        # connected before the 6 s are counted: a command sent earlier waits for the connection
        pub = command_publisher("/cmd_vel", Twist, 60)
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
        p = o.pose.pose.position

        def gap():
            poses = [m.pose[m.name.index("polaris")].position for m in list(states) if "polaris" in m.name]
            return min((math.sqrt((q.x - p.x) ** 2 + (q.y - p.y) ** 2 + (q.z - p.z) ** 2) for q in poses),
                       default=float("inf"))
        # this process may still be deserialising the model_states that odometry relayed
        try:
            wait_until(lambda: gap() < 1e-9, 10.0, "the model_states that /odom relayed")
        except AssertionError:
            self.fail("/odom's pose is none of the model_states poses (%.3g m away)" % gap())
        tr = buf.lookup_transform("odom", "base_link_polaris", o.header.stamp, rospy.Duration(10.0))
        self.assertAlmostEqual(tr.transform.translation.x, o.pose.pose.position.x, delta=0.01)
        # stale commands stop the vehicle (Ackermann node's timeout): within 4 s of simulated time by
        # the stamp of the first odometry that says so (waited for in wall time)
        t1 = rospy.get_time()
        stopped = wait_until(lambda: odom["m"] if abs(odom["m"].twist.twist.linear.x) < 0.05 else None, 60,
                             "the vehicle stopped after its last command")
        self.assertLessEqual(stopped.header.stamp.to_sec() - t1, 4.0, "stopped %.2f s after the last command"
                             % (stopped.header.stamp.to_sec() - t1))


if __name__ == "__main__":
    rospy.init_node("polaris_drive_check")
    rostest.rosrun("polaris_description", "polaris_drive", PolarisDrive)
