#!/usr/bin/env python3
"""rostest node: a node given an invalid order reports the position and the ID (in its ~status
parameter and its error log), publishes no description, and keeps running."""
import unittest

import rosnode
import rospy
import rostest


class RefusalCheck(unittest.TestCase):
    def test_refused_nothing_published_still_running(self):
        node = rospy.get_param("~node")
        fragments = rospy.get_param("~fragments")
        deadline = rospy.Time.now() + rospy.Duration(30)
        while not rospy.has_param(node + "/status") and rospy.Time.now() < deadline:
            rospy.sleep(0.05)
        status = rospy.get_param(node + "/status", None)
        self.assertIsNotNone(status, "%s set no status within 30 s" % node)
        self.assertTrue(status.startswith("refused: "), status)
        for f in fragments:
            self.assertIn(f, status)
        self.assertFalse(rospy.has_param("/modrob_robots"))
        self.assertFalse(rospy.has_param("/modrob0/robot_description"))
        self.assertTrue(rosnode.rosnode_ping(node, max_count=1), "%s is not running any more" % node)


if __name__ == "__main__":
    rospy.init_node("refusal_check")
    rostest.rosrun("modrob_build", "refusal_check", RefusalCheck)
