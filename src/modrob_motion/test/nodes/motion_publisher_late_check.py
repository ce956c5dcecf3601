#!/usr/bin/env python3
"""A controller that appears after motion_publisher started is picked up on the first command that
names its joint, and without any command by the node's watch on the parameters (a command without
joint names, every joint in order, reaches it); a joint that never appears is still refused and the
node keeps running."""
import sys
import threading
import unittest

import rospy
import rostest
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64


class LateControllers(unittest.TestCase):
    def test_controller_added_after_start_gets_commands(self):
        rospy.init_node("motion_publisher_late_check")
        got = {}
        events = {j: threading.Event() for j in ("joint1", "joint2", "joint3")}

        def on(joint):
            def cb(msg):
                got[joint] = msg.data
                events[joint].set()
            return cb
        rospy.Subscriber("/late_bot/joint1_position_controller/command", Float64, on("joint1"))
        rospy.Subscriber("/late_bot/joint2_position_controller/command", Float64, on("joint2"))
        rospy.Subscriber("/late_bot/joint3_position_controller/command", Float64, on("joint3"))
        pub = rospy.Publisher("/late_bot/motion_command", JointState, queue_size=10)
        # the node is up once it subscribes to motion_command
        deadline = rospy.get_time() + 30.0
        while pub.get_num_connections() == 0 and rospy.get_time() < deadline:
            rospy.sleep(0.05)
        self.assertGreater(pub.get_num_connections(), 0, "motion_publisher never subscribed")
        rospy.set_param("/late_bot/joint2_position_controller",
                        {"type": "effort_controllers/JointPositionController", "joint": "joint2",
                         "pid": {"p": 100.0, "i": 0.0, "d": 1.0}})
        # (re-sent until both arrive: the first messages on a new command topic can go before its
        # subscriber has connected)
        deadline = rospy.get_time() + 20.0
        while not (events["joint1"].is_set() and events["joint2"].is_set()) and rospy.get_time() < deadline:
            pub.publish(JointState(name=["joint1", "joint2"], position=[0.1, 0.2]))
            events["joint2"].wait(0.3)
        self.assertTrue(events["joint2"].is_set(), "the late controller joint2 never got a command")
        self.assertAlmostEqual(got["joint2"], 0.2)
        self.assertAlmostEqual(got.get("joint1"), 0.1)
        # a joint that does not exist: dropped, and the node keeps serving the others
        events["joint1"].clear()
        pub.publish(JointState(name=["joint1", "joint9"], position=[0.3, 0.0]))
        pub.publish(JointState(name=["joint1"], position=[0.4]))
        deadline = rospy.get_time() + 10.0
        while got.get("joint1") != 0.4 and rospy.get_time() < deadline:
            events["joint1"].wait(0.2)
            events["joint1"].clear()
        self.assertAlmostEqual(got["joint1"], 0.4)
        # joint3's controller appears and no command names it: commands without names (every joint
        # in order) reach it once the node has seen the new parameters
        rospy.set_param("/late_bot/joint3_position_controller",
                        {"type": "effort_controllers/JointPositionController", "joint": "joint3",
                         "pid": {"p": 100.0, "i": 0.0, "d": 1.0}})
        deadline = rospy.get_time() + 20.0
        while not events["joint3"].is_set() and rospy.get_time() < deadline:
            pub.publish(JointState(position=[0.5, 0.6, 0.7]))
            events["joint3"].wait(0.3)
        self.assertTrue(events["joint3"].is_set(), "joint3's controller, added without a command naming it, "
                        "never got a command")
        self.assertAlmostEqual(got["joint3"], 0.7)


if __name__ == "__main__":
    rostest.rosrun("modrob_motion", "motion_publisher_late", LateControllers, sys.argv)
