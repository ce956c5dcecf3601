#!/usr/bin/env python3
"""rostest: 3700 joint points through recorder, bag and KDL visualiser lose nothing."""
import unittest

import numpy as np
import rospy
import rostest
from std_msgs.msg import Int32
from trajectory_msgs.msg import JointTrajectory
from visualization_msgs.msg import Marker, MarkerArray

from modrob_kinematics import kdl_urdf
from modrob_viz import bag_io, joint_path, samples
from modrob_viz.ros.demo_motion import trajectory_msg
from viz_test_utils import wait_for

N = 3700


class JointTrajectoryPipeline(unittest.TestCase):
    def test_lossless_record_and_fk_replay(self):
        tree = kdl_urdf.tree_from_urdf_string(rospy.get_param("/robot_description"))
        path = samples.sample_joint_trajectory(tree.joint_names, tree.limits, N)
        pub = rospy.Publisher("/tp_rv_topic", JointTrajectory, queue_size=1, latch=True)
        pub.publish(trajectory_msg(path))

        count = wait_for("/joint_trajectory_recorder/recorded_points", Int32, lambda m: m.data >= N, 30)
        self.assertIsNotNone(count, "the recorder did not report %d recorded points" % N)
        self.assertEqual(count.data, N)
        back = bag_io.read_joint_trajectory(rospy.get_param("~bag_file"))
        self.assertEqual(back.names, tree.joint_names)
        self.assertEqual(len(back), N)
        self.assertTrue(np.array_equal(back.positions, path.positions),
                        "bag positions differ from those sent")

        strip = wait_for("/joint_trajectory_visualizer/marker", Marker, lambda m: len(m.points) == N, 30)
        self.assertIsNotNone(strip, "no LINE_STRIP with %d points from joint_trajectory_visualizer" % N)
        self.assertEqual(strip.type, Marker.LINE_STRIP)
        self.assertEqual(strip.header.frame_id, "world")
        expect = joint_path.end_effector_path(tree, path, "ee_link")
        got = np.array([(p.x, p.y, p.z) for p in strip.points])
        self.assertTrue(np.array_equal(got, expect), "strip points differ from KDL FK of the sent points")
        chain = kdl_urdf.KinematicChain(tree, "world", "ee_link")
        for i in (0, 1850, N - 1):  # the chain solver agrees with the tree walk
            np.testing.assert_allclose(got[i], chain.fk_position(path.positions[i]), atol=1e-12)

        arrows = wait_for("/joint_trajectory_visualizer/arrows", MarkerArray, lambda m: len(m.markers) > 1,
                          10)
        self.assertIsNotNone(arrows, "no direction arrows")
        self.assertTrue(all(m.type == Marker.ARROW for m in arrows.markers[1:]))
        milestones = wait_for("/joint_trajectory_visualizer/milestones", Marker, timeout=10)
        reduced = wait_for("/joint_trajectory_visualizer/reduced_trajectory", JointTrajectory, timeout=10)
        self.assertIsNotNone(milestones)
        self.assertIsNotNone(reduced)
        self.assertEqual(len(milestones.points), len(reduced.points))
        self.assertLess(len(reduced.points), N / 10)


if __name__ == "__main__":
    rospy.init_node("check_joint_trajectory_pipeline")
    rostest.rosrun("modrob_viz", "check_joint_trajectory_pipeline", JointTrajectoryPipeline)
