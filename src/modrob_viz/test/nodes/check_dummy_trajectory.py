#!/usr/bin/env python3
"""rostest: a 3700-point helix from dummy_trajectory_publisher through a bag to a LINE_STRIP,
values identical; the points are also streamed as PointStamped."""
import unittest

import rospy
import rostest
from geometry_msgs.msg import PointStamped
from visualization_msgs.msg import Marker, MarkerArray

from modrob_viz import bag_io, paths
from viz_test_utils import wait_for

N = 3700


class DummyTrajectory(unittest.TestCase):
    def test_helix_round_trip(self):
        expect = paths.helix(n=N)
        strip = wait_for("/trajectory_3Dpoints_visualizer/marker", Marker, lambda m: len(m.points) == N, 30)
        self.assertIsNotNone(strip, "no LINE_STRIP of %d points" % N)
        self.assertEqual([(p.x, p.y, p.z) for p in strip.points], expect)
        points, frame = bag_io.read_points(rospy.get_param("~bag_file"))
        self.assertEqual((points, frame), (expect, "world"))
        arrows = wait_for("/trajectory_3Dpoints_visualizer/arrows", MarkerArray,
                          lambda m: len(m.markers) > 5, 10)
        self.assertIsNotNone(arrows, "no direction arrows along the helix")
        streamed = wait_for("/dummy_trajectory_publisher/points", PointStamped, timeout=10)
        self.assertIsNotNone(streamed, "no PointStamped stream")
        self.assertEqual(streamed.header.frame_id, "world")
        preview = wait_for("/dummy_trajectory_publisher/marker", Marker, timeout=10)
        self.assertEqual(len(preview.points), N)


if __name__ == "__main__":
    rospy.init_node("check_dummy_trajectory")
    rostest.rosrun("modrob_viz", "check_dummy_trajectory", DummyTrajectory)
