#!/usr/bin/env python3
"""rostest: the trace is a LINE_STRIP in world that grows and follows the end effector."""
import math
import unittest

import rospy
import rostest
import tf2_ros
from visualization_msgs.msg import Marker

from viz_test_utils import wait_for


class Trace(unittest.TestCase):
    def test_trace_grows_along_the_end_effector(self):
        buffer = tf2_ros.Buffer()
        tf2_ros.TransformListener(buffer)
        first = wait_for("/trace_visualizer/marker", Marker, lambda m: len(m.points) >= 5, 30)
        self.assertIsNotNone(first, "no trace with 5 points within 30 s")
        self.assertEqual(first.type, Marker.LINE_STRIP)
        self.assertEqual(first.header.frame_id, "world")
        later = wait_for("/trace_visualizer/marker", Marker,
                         lambda m: len(m.points) >= len(first.points) + 20, 30)
        self.assertIsNotNone(later, "the trace stopped growing")
        # the newest point is where tf says the end effector was a moment ago (it moves slowly)
        t = buffer.lookup_transform("world", "ee_link", rospy.Time(0), rospy.Duration(5))
        p, q = later.points[-1], t.transform.translation
        self.assertLess(math.dist((p.x, p.y, p.z), (q.x, q.y, q.z)), 0.1)
        spread = max(math.dist((a.x, a.y, a.z), (later.points[0].x, later.points[0].y, later.points[0].z))
                     for a in later.points)
        self.assertGreater(spread, 0.05, "the trace does not move although the robot does")


if __name__ == "__main__":
    rospy.init_node("check_trace")
    rostest.rosrun("modrob_viz", "check_trace_visualizer", Trace)
