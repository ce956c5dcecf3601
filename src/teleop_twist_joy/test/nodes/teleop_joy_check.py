#!/usr/bin/env python3
"""rostest node for teleop_twist_joy.test."""
import unittest

import rospy
import rostest
from geometry_msgs.msg import Twist
from sensor_msgs.msg import Joy

from modrob_sim.waits import wait_until


class TeleopJoy(unittest.TestCase):
    def test_enable_turbo_and_release(self):
        rospy.init_node("teleop_joy_check")
        got = []
        rospy.Subscriber("/joy_teleop/cmd_vel", Twist, lambda m: got.append((m.linear.x, m.angular.z)),
                         queue_size=100)
        pub = rospy.Publisher("/joy_teleop/joy", Joy, queue_size=10)
        wait_until(lambda: pub.get_num_connections() > 0, 30, "teleop_node subscribing to joy")

        def joy(axes, buttons):
            pub.publish(Joy(axes=axes, buttons=buttons))
        joy([0.5, 1.0], [0, 0, 0, 0, 1, 0])
        wait_until(lambda: (0.4, 0.7) in got, 10, "0.4 m/s and 0.7 rad/s with L1 held")
        joy([0.0, 1.0], [0, 0, 0, 0, 1, 1])
        wait_until(lambda: (2.0, 0.0) in got, 10, "turbo 2.0 m/s")
        joy([0.0, 1.0], [0, 0, 0, 0, 0, 0])
        wait_until(lambda: got[-1] == (0.0, 0.0), 10, "one zero twist on release")
        n = len(got)
        joy([0.0, 1.0], [0, 0, 0, 0, 0, 0])
        joy([0.3, 0.0], [0, 0, 0, 0, 1, 0])                 # the next message says it got through
        wait_until(lambda: len(got) > n, 10, "the next twist")
        self.assertEqual(len(got), n + 1)                   # no second zero in between
        self.assertAlmostEqual(got[n][1], 0.3 * 1.4, places=6)      # Joy axes are float32


if __name__ == "__main__":
    rostest.rosrun("teleop_twist_joy", "teleop_joy_check", TeleopJoy)
