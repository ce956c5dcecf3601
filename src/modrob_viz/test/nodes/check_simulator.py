#!/usr/bin/env python3
"""rostest: the simulator plays 740 of 3700 points, the model follows (divergence ~0), it publishes
RobotConfigMeasured, dims the passed path, and survives a trajectory with unknown joints."""
import threading
import unittest

import rospy
import rostest
from modrob_msgs.msg import RobotConfigMeasured
from rosgraph_msgs.msg import Log
from std_msgs.msg import Float64, Int32
from trajectory_msgs.msg import JointTrajectory
from visualization_msgs.msg import Marker

from modrob_kinematics import kdl_urdf
from modrob_viz import samples
from modrob_viz.ros.demo_motion import trajectory_msg
from viz_test_utils import RosoutWatcher, alive, wait_for

NODE = "/joint_trajectory_simulator"


class Simulator(unittest.TestCase):
    def test_play_measure_and_refuse_bad_joints(self):
        tree = kdl_urdf.tree_from_urdf_string(rospy.get_param("/robot_description"))
        rosout = RosoutWatcher()
        configs = []
        lock = threading.Lock()

        def on_config(msg):
            with lock:
                configs.append(msg)
        rospy.Subscriber("/modrob0/robot_config_measured", RobotConfigMeasured, on_config, queue_size=1000)
        pub = rospy.Publisher("/tp_rv_topic", JointTrajectory, queue_size=1, latch=True)
        path = samples.sample_joint_trajectory(tree.joint_names, tree.limits, 3700)
        pub.publish(trajectory_msg(path))

        played = wait_for(NODE + "/played_points", Int32, lambda m: m.data > 0, 60)
        self.assertIsNotNone(played, "the simulator did not finish playing")
        self.assertEqual(played.data, 740)  # the last of every 5 of 3700
        div_max = wait_for(NODE + "/divergence_max", Float64, timeout=5)
        div_rms = wait_for(NODE + "/divergence_rms", Float64, timeout=5)
        self.assertLess(div_max.data, 1e-6, "tf path diverges from the KDL path by %g m" % div_max.data)
        self.assertLessEqual(div_rms.data, div_max.data)
        with lock:
            self.assertGreaterEqual(len(configs), 700)
            self.assertEqual(list(configs[-1].joint_names), tree.joint_names)
            self.assertEqual(list(configs[-1].joint_angles), path.positions[-1].tolist())
        desired = wait_for(NODE + "/desired", Marker,
                           lambda m: len(m.colors) == 3700 and m.colors[-1].a < 0.5, 5)
        self.assertIsNotNone(desired, "the passed desired path is not dimmed at the end")
        travelled = wait_for(NODE + "/travelled", Marker, timeout=5)
        self.assertGreater(len(travelled.points), 10)
        self.assertIsNotNone(rosout.wait_for(NODE, Log.INFO, "divergence", 5))

        bad = trajectory_msg(samples.sample_joint_trajectory(["shoulder", "elbow"], {"shoulder": (-1, 1),
                                                                                     "elbow": (-1, 1)}, 50))
        pub.publish(bad)
        err = rosout.wait_for(NODE, Log.ERROR, "shoulder, elbow", 15)
        self.assertIsNotNone(err, "no error naming the unknown joints")
        self.assertIn("lacks", err.msg)
        self.assertTrue(alive(NODE), "the simulator died on a bad trajectory")
        pub.publish(trajectory_msg(samples.sample_joint_trajectory(tree.joint_names, tree.limits, 100)))
        again = wait_for(NODE + "/played_points", Int32, lambda m: m.data == 20, 30)
        self.assertIsNotNone(again, "the simulator did not play a good trajectory after a bad one")


if __name__ == "__main__":
    rospy.init_node("check_simulator")
    rostest.rosrun("modrob_viz", "check_joint_trajectory_simulator", Simulator)
