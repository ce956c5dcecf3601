#!/usr/bin/env python3
"""rostest for both control-device user tests: drive the robot far from and then (IK) onto the
goal / trajectory and check the sphere colour, the published distances and the CSV/PNG log."""
import math
import os
import unittest

import rospy
import rostest
from std_msgs.msg import Bool, Float64
from visualization_msgs.msg import Marker

from modrob_kinematics import kdl_urdf
from modrob_viz import paths
from modrob_viz.distance_log import DistanceLog
from modrob_viz.geometry import PolylineDistance
from viz_test_utils import RobotDriver, wait_for

MM = 1e-3


class UserTest(unittest.TestCase):
    def setUp(self):
        self.node = rospy.get_param("~node")
        self.chain = kdl_urdf.KinematicChain.from_urdf_string(rospy.get_param("/robot_description"))
        self.goal = rospy.get_param(self.node + "/goal", None)
        self.threshold = rospy.get_param(self.node + "/threshold")
        self.driver = RobotDriver("world", "ee_link")

    def drive(self, q):
        t = self.driver.move(self.chain.joint_names, q)
        self.assertIsNotNone(t, "tf did not follow joint_states")
        p = self.chain.fk_position(q)
        tp = t.transform.translation
        self.assertLess(math.dist(p, (tp.x, tp.y, tp.z)), 1e-6)
        return p

    def distance_after(self, topic, since):
        """A distance published after the robot reached its configuration."""
        msg = None
        deadline = rospy.get_time() + 10
        while rospy.get_time() < deadline:
            msg = wait_for(topic, Float64, timeout=5)
            if msg is not None and rospy.get_time() - since > 0.3:
                return msg.data
        self.fail("no %s published" % topic)

    def test_distances_colour_and_log(self):
        goal = self.goal
        if goal is None:  # the trajectory test's goal is the end of its path
            goal = wait_for(self.node + "/goal_marker", Marker, timeout=20).pose.position
            goal = [goal.x, goal.y, goal.z]
        sphere = wait_for(self.node + "/goal_marker", Marker, timeout=20)
        self.assertIsNotNone(sphere, "no goal sphere")
        self.assertEqual(sphere.type, Marker.SPHERE)
        self.assertEqual(sphere.header.frame_id, "world")
        self.assertGreater(sphere.color.r, 0.9, "the sphere is not red at the start")

        far = [0.0] * self.chain.n_joints
        p = self.drive(far)
        t0 = rospy.get_time()
        d = self.distance_after("/distance_to_endpoint", t0)
        self.assertAlmostEqual(d, math.dist(p, goal), delta=MM)
        self.assertGreater(d, self.threshold)

        trajectory = None
        if self.node.endswith("trajectory"):
            shape = rospy.get_param(self.node + "/shape_params")
            trajectory = PolylineDistance(paths.generate(rospy.get_param(self.node + "/shape"), **shape))
            dt = self.distance_after("/distance_to_trajectory", t0)
            self.assertAlmostEqual(dt, trajectory.distance(p), delta=MM)
            path_point = trajectory.points[len(trajectory.points) // 3]
            q_on = self.chain.ik(tuple(path_point), q0=[0.3, -0.5, 1.2, 0.6])
            p = self.drive(q_on)
            dt = self.distance_after("/distance_to_trajectory", rospy.get_time())
            self.assertLess(dt, MM)
            self.assertAlmostEqual(dt, trajectory.distance(p), delta=MM)

        q_goal = self.chain.ik(tuple(goal), q0=[0.3, -0.5, 1.2, 0.6])
        p = self.drive(q_goal)
        d = self.distance_after("/distance_to_endpoint", rospy.get_time())
        self.assertAlmostEqual(d, math.dist(p, goal), delta=MM)
        self.assertLess(d, self.threshold)
        reached = wait_for(self.node + "/goal_reached", Bool, lambda m: m.data, 10)
        self.assertIsNotNone(reached, "goal_reached did not turn true")
        green = wait_for(self.node + "/goal_marker", Marker, lambda m: m.color.g > 0.5 and m.color.r < 0.5,
                         10)
        self.assertIsNotNone(green, "the sphere did not change colour inside the threshold")

        out = rospy.get_param("~out")
        # the node writes the files every save_period (whole files, renamed into place); the first
        # PNG includes matplotlib's import, which took more than 10 s on a loaded CI machine. The
        # first CSV can be written before six samples (its timer lags under load): wait for the
        # log to grow, as it does with every save
        deadline = rospy.get_time() + 45
        log = []
        while rospy.get_time() < deadline and not (len(log) > 5 and os.path.exists(out + ".png")):
            rospy.sleep(0.2)
            log = DistanceLog.read_csv(out + ".csv") if os.path.exists(out + ".csv") else []
        for ext in (".csv", ".png"):
            self.assertTrue(os.path.exists(out + ext), "%s%s not written within 45 s" % (out, ext))
        self.assertGreater(len(log), 5, "%s.csv holds %d rows after 45 s" % (out, len(log)))
        if trajectory is not None:
            self.assertTrue(any(not math.isnan(r[2]) for r in log.rows))
        with open(out + ".png", "rb") as f:
            self.assertEqual(f.read(4), b"\x89PNG")


if __name__ == "__main__":
    rospy.init_node("check_usertest")
    rostest.rosrun("modrob_viz", "check_usertest", UserTest)
