#!/usr/bin/env python3
"""rostest node for marker_server.test: the marker on /twist_marker_server/update_full, and drags
sent as an RViz client sends them (InteractiveMarkerFeedback) turned into twists."""
import math
import time
import unittest

import rospy
import rostest
from geometry_msgs.msg import Twist
from visualization_msgs.msg import InteractiveMarkerFeedback, InteractiveMarkerInit

from modrob_sim.waits import wait_until


class MarkerServer(unittest.TestCase):
    def test_marker_and_drags(self):
        rospy.init_node("marker_check")
        inits, twists = [], []
        rospy.Subscriber("/twist_marker_server/update_full", InteractiveMarkerInit, inits.append,
                         queue_size=10)
        rospy.Subscriber("/twist_marker_server/cmd_vel", Twist, twists.append, queue_size=10)
        wait_until(lambda: inits and inits[-1].markers, 30, "the marker on update_full")
        im = inits[-1].markers[0]
        self.assertEqual((im.name, im.header.frame_id), ("robot_twist_marker", "base_link"))
        self.assertEqual([c.name for c in im.controls], ["move_x", "rotate_z"])
        fb_pub = rospy.Publisher("/twist_marker_server/feedback", InteractiveMarkerFeedback, queue_size=10)
        wait_until(lambda: fb_pub.get_num_connections() > 0, 30, "the server subscribing to feedback")

        def drag(x, yaw):
            """A drag as RViz sends it: pose updates while the mouse moves (here until a twist comes;
            the server takes no feedback from a new client in the first second after an insert)."""
            n = len(twists)
            fb = InteractiveMarkerFeedback(client_id="test", marker_name="robot_twist_marker",
                                           control_name="move_x",
                                           event_type=InteractiveMarkerFeedback.POSE_UPDATE)
            fb.header.frame_id = "base_link"
            fb.pose.position.x = x
            fb.pose.orientation.z, fb.pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
            end = time.monotonic() + 10
            while len(twists) == n and time.monotonic() < end:
                fb_pub.publish(fb)
                time.sleep(0.1)                  # RViz's pace of pose updates during a drag
        drag(0.4, 0.25)
        wait_until(lambda: twists, 10, "a twist on /twist_marker_server/cmd_vel")
        self.assertAlmostEqual(twists[-1].linear.x, 0.4)
        self.assertAlmostEqual(twists[-1].angular.z, 0.55)
        n = len(twists)
        drag(5.0, 0.0)
        wait_until(lambda: len(twists) > n, 10, "a second twist")
        self.assertAlmostEqual(twists[-1].linear.x, 1.0)            # max_positive_linear_velocity


if __name__ == "__main__":
    rostest.rosrun("interactive_marker_twist_server", "marker_check", MarkerServer)
