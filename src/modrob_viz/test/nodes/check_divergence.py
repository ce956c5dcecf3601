#!/usr/bin/env python3
"""rostest: a robot that follows RobotConfigMeasured with joint2 off by 0.1 rad is reported as
diverging, by about as much as that offset moves the end effector away from the desired path."""
import unittest

import numpy as np
import rospy
import rostest
from modrob_msgs.msg import RobotConfigMeasured
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64, Int32
from trajectory_msgs.msg import JointTrajectory

from modrob_kinematics import kdl_urdf
from modrob_viz import geometry, joint_path, samples
from modrob_viz.ros.demo_motion import trajectory_msg
from viz_test_utils import wait_for

NODE = "/joint_trajectory_simulator"
OFFSET = 0.1


class Divergence(unittest.TestCase):
    def test_offset_robot_diverges(self):
        tree = kdl_urdf.tree_from_urdf_string(rospy.get_param("/robot_description"))
        js_pub = rospy.Publisher("/joint_states", JointState, queue_size=100)

        def follow(config):  # the stand-in robot: joint2 misses its target by OFFSET
            q = list(config.joint_angles)
            q[config.joint_names.index("joint2")] += OFFSET
            msg = JointState(name=list(config.joint_names), position=q)
            msg.header.stamp = rospy.Time.now()
            js_pub.publish(msg)
        rospy.Subscriber("/modrob0/robot_config_measured", RobotConfigMeasured, follow, queue_size=100)
        path = samples.sample_joint_trajectory(tree.joint_names, tree.limits, 1000)
        pub = rospy.Publisher("/tp_rv_topic", JointTrajectory, queue_size=1, latch=True)
        pub.publish(trajectory_msg(path))

        self.assertIsNotNone(wait_for(NODE + "/played_points", Int32, lambda m: m.data == 200, 60))
        div_max = wait_for(NODE + "/divergence_max", Float64, timeout=5).data
        # the same measure, computed here from the played points with the offset applied
        played = path.subset(joint_path.decimate(len(path), 5))
        offset = played.positions.copy()
        offset[:, tree.joint_names.index("joint2")] += OFFSET
        ee_desired = joint_path.end_effector_path(tree, path, "ee_link")
        ee_offset = joint_path.end_effector_path(tree, joint_path.JointPath(path.names, offset), "ee_link")
        expect = geometry.divergence(ee_desired, ee_offset)
        self.assertGreater(div_max, 0.01, "a 0.1 rad offset went unnoticed")
        self.assertLessEqual(div_max, expect.max + 1e-6)
        self.assertGreater(div_max, 0.5 * expect.max)
        self.assertTrue(np.isfinite(wait_for(NODE + "/divergence_rms", Float64, timeout=5).data))


if __name__ == "__main__":
    rospy.init_node("check_divergence")
    rostest.rosrun("modrob_viz", "check_joint_trajectory_divergence", Divergence)
