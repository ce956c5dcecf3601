#!/usr/bin/env python3
"""rostest: end-effector points recorded from tf reach the bag and come back as a LINE_STRIP
with the same values; the recorder publishes nothing to visualise itself."""
import math
import unittest

import rospy
import rostest
from std_msgs.msg import Int32
from visualization_msgs.msg import Marker

from modrob_kinematics import kdl_urdf
from modrob_viz import bag_io
from viz_test_utils import wait_for


class Trajectory3D(unittest.TestCase):
    def test_record_then_show(self):
        count = wait_for("/trajectory_3Dpoints_recorder/recorded_points", Int32, lambda m: m.data >= 30, 30)
        self.assertIsNotNone(count, "fewer than 30 points recorded in 30 s")
        strip = wait_for("/trajectory_3Dpoints_visualizer/marker", Marker, lambda m: len(m.points) >= 30, 15)
        self.assertIsNotNone(strip, "the visualiser did not show the recorded points")
        self.assertEqual(strip.type, Marker.LINE_STRIP)
        self.assertEqual(strip.header.frame_id, "world")
        points, frame = bag_io.read_points(rospy.get_param("~bag_file"))
        self.assertEqual(frame, "world")
        shown = [(p.x, p.y, p.z) for p in strip.points]
        self.assertEqual(shown, points[:len(shown)], "shown points differ from the bag")
        chain = kdl_urdf.KinematicChain.from_urdf_string(rospy.get_param("/robot_description"))
        self.assertTrue(all(math.dist(p, (0, 0, 0)) <= chain.reach + 1e-6 for p in points))
        topics = [t for t, _ in rospy.get_published_topics()]
        self.assertFalse(any(t.startswith("/trajectory_3Dpoints_recorder/marker") for t in topics))


if __name__ == "__main__":
    rospy.init_node("check_trajectory_3d")
    rostest.rosrun("modrob_viz", "check_trajectory_3d", Trajectory3D)
