#!/usr/bin/env python3
"""rostest node: the spawn_model script with gazebo_ros's flags: from -param and from -file
(exit 0, the model where -x -y -z -Y put it, -J joints set while running), and failures (exit 1
with a message): a missing file, a malformed file, a missing parameter, a duplicate name."""
import math
import os
import subprocess
import sys
import unittest

import rospy
import rostest

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from sim_helpers import FIXTURES, Gazebo, fixture  # noqa: E402


SCRIPT = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))),
                      "scripts", "spawn_model")


def run_spawn(*args, stdin=None, timeout=60):
    p = subprocess.run([sys.executable, SCRIPT] + list(args), input=stdin, timeout=timeout,
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True)
    return p.returncode, p.stdout


class SimSpawnModel(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.gz = Gazebo()

    def test_from_param_with_pose(self):
        rospy.set_param("/box_description", fixture("box.urdf"))
        rc, out = run_spawn("-urdf", "-param", "box_description", "-model", "pbox", "-x", "1.5", "-y", "-0.5",
                            "-z", "2.0", "-Y", "0.4")
        self.assertEqual(rc, 0, out)
        self.gz.pause_physics()
        s = self.gz.get_model_state(model_name="pbox", relative_entity_name="world")
        self.gz.unpause_physics()
        self.assertTrue(s.success, s.status_message)
        self.assertAlmostEqual(s.pose.position.x, 1.5, places=2)
        self.assertAlmostEqual(s.pose.position.y, -0.5, places=2)
        q = s.pose.orientation
        self.assertAlmostEqual(2 * math.atan2(q.z, q.w), 0.4, places=2)

    def test_from_file_with_joints_while_running(self):
        rc, out = run_spawn("-urdf", "-file", os.path.join(FIXTURES, "arm2.urdf"), "-model", "farm",
                            "-y", "3", "-J", "shoulder", "0.8", "-J", "elbow", "-0.6", "-unpause")
        self.assertEqual(rc, 0, out)
        self.assertFalse(self.gz.get_physics_properties().pause)
        # the shoulder turns about the vertical: gravity does not move it, so it stays where -J put
        # it (the elbow, unactuated, falls under gravity as it should)
        self.assertAlmostEqual(self.gz.get_joint_properties(joint_name="farm::shoulder").position[0], 0.8,
                               delta=0.02)

    def test_from_stdin(self):
        rc, out = run_spawn("-urdf", "-stdin", "-model", "sbox", "-x", "-3", stdin=fixture("box.urdf"))
        self.assertEqual(rc, 0, out)
        self.assertIn("sbox", self.gz.get_world_properties().model_names)

    def test_missing_file_exits_1(self):
        rc, out = run_spawn("-urdf", "-file", "/nonexistent/robot.urdf", "-model", "x")
        self.assertEqual(rc, 1, out)
        self.assertIn("/nonexistent/robot.urdf does not exist", out)

    def test_malformed_file_exits_1(self):
        rc, out = run_spawn("-urdf", "-file", os.path.join(FIXTURES, "malformed.urdf"), "-model", "bad")
        self.assertEqual(rc, 1, out)
        self.assertIn("invalid XML", out)

    def test_missing_param_exits_1(self):
        rc, out = run_spawn("-urdf", "-param", "no_such_description", "-model", "x")
        self.assertEqual(rc, 1, out)
        self.assertIn("no_such_description does not exist", out)

    def test_duplicate_name_exits_1_with_the_simulators_reason(self):
        path = os.path.join(FIXTURES, "box.urdf")
        rc, out = run_spawn("-urdf", "-file", path, "-model", "twice", "-x", "4")
        self.assertEqual(rc, 0, out)
        rc, out = run_spawn("-urdf", "-file", path, "-model", "twice", "-x", "4")
        self.assertEqual(rc, 1, out)
        self.assertIn("already exists", out)

    def test_wait_for_an_existing_model(self):
        path = os.path.join(FIXTURES, "box.urdf")
        self.assertEqual(run_spawn("-urdf", "-file", path, "-model", "first", "-x", "8")[0], 0)
        rc, out = run_spawn("-urdf", "-file", path, "-model", "second", "-x", "9", "-wait", "first")
        self.assertEqual(rc, 0, out)
        self.assertIn("second", self.gz.get_world_properties().model_names)

    def test_unknown_joint_in_J_exits_1(self):
        rc, out = run_spawn("-urdf", "-file", os.path.join(FIXTURES, "arm2.urdf"), "-model", "jarm",
                            "-x", "6", "-J", "wrist", "0.1")
        self.assertEqual(rc, 1, out)
        self.assertIn("wrist", out)


if __name__ == "__main__":
    rospy.init_node("sim_spawn_model_test")
    rostest.rosrun("modrob_sim", "sim_spawn_model", SimSpawnModel)
