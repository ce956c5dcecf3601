#!/usr/bin/env python3
"""rostest: bad bags, unknown joints and a missing/malformed robot description are reported by
name; long-running nodes stay up, start-up failures exit with code 2, never with a traceback."""
import os
import signal
import subprocess
import threading
import time
import unittest

import rospkg
import rospy
import rostest

FIXTURES = os.path.join(rospkg.RosPack().get_path("modrob_viz"), "test", "fixtures")


class NodeProcess(object):
    """A modrob_viz node run with rosrun against this test's master, its output collected."""

    def __init__(self, script, *args):
        self.proc = subprocess.Popen(["rosrun", "modrob_viz", script] + list(args), stdout=subprocess.PIPE,
                                     stderr=subprocess.STDOUT, env=dict(os.environ), start_new_session=True)
        self.output = []
        self.reader = threading.Thread(target=self._read, daemon=True)
        self.reader.start()

    def _read(self):
        for line in iter(self.proc.stdout.readline, b""):
            self.output.append(line.decode(errors="replace"))

    @property
    def text(self):
        return "".join(self.output)

    def wait_for_text(self, text, timeout=30.0):
        deadline = time.time() + timeout
        while time.time() < deadline:
            if text in self.text:
                return True
            time.sleep(0.1)
        return False

    def wait_exit(self, timeout=30.0):
        code = self.proc.wait(timeout)
        self.reader.join(5)
        return code

    def stop(self):
        if self.proc.poll() is None:
            os.killpg(self.proc.pid, signal.SIGINT)
            try:
                self.proc.wait(15)
            except subprocess.TimeoutExpired:
                os.killpg(self.proc.pid, signal.SIGKILL)
        self.reader.join(5)


class BadInput(unittest.TestCase):
    def test_points_bag_without_the_topic(self):
        node = NodeProcess("trajectory_3Dpoints_visualizer", "__name:=vis_bad_bag",
                           "_bag_file:=" + os.path.join(FIXTURES, "no_points_topic_bad.bag"))
        try:
            self.assertTrue(node.wait_for_text("has no topic '/trajectory_3d/points'"), node.text)
            self.assertIn("/somewhere_else", node.text)
            time.sleep(1.0)
            self.assertIsNone(node.proc.poll(), "the visualiser exited on a bad bag:\n" + node.text)
        finally:
            node.stop()
        self.assertNotIn("Traceback", node.text)

    def test_joint_bag_with_joints_the_robot_lacks(self):
        node = NodeProcess("joint_trajectory_simulator", "__name:=sim_bad_joints",
                           "_bag_file:=" + os.path.join(FIXTURES, "wrong_joints_bad.bag"))
        try:
            self.assertTrue(node.wait_for_text("wrist_roll"), node.text)
            self.assertIn("lacks", node.text)
            time.sleep(1.0)
            self.assertIsNone(node.proc.poll(), "the simulator exited on a bad trajectory:\n" + node.text)
        finally:
            node.stop()
        self.assertNotIn("Traceback", node.text)

    def test_missing_robot_description_exits_with_code_2(self):
        node = NodeProcess("joint_trajectory_visualizer", "__name:=no_description",
                           "_robot_description_param:=/no_such_description", "_description_timeout:=1")
        self.assertEqual(node.wait_exit(), 2, node.text)
        self.assertIn("/no_such_description is not set", node.text)
        self.assertNotIn("Traceback", node.text)

    def test_malformed_robot_description_exits_with_code_2(self):
        rospy.set_param("/broken_description", "<robot name='x'><link name='a'/><joint")
        node = NodeProcess("joint_trajectory_simulator", "__name:=bad_urdf",
                           "_robot_description_param:=/broken_description")
        self.assertEqual(node.wait_exit(), 2, node.text)
        self.assertIn("not a valid URDF", node.text)
        self.assertIn("/broken_description", node.text)
        self.assertNotIn("Traceback", node.text)

    def test_bad_parameter_exits_with_code_2(self):
        node = NodeProcess("trace_visualizer", "__name:=bad_colour", "_color:=ultraviolet")
        self.assertEqual(node.wait_exit(), 2, node.text)
        self.assertIn("ultraviolet", node.text)
        self.assertNotIn("Traceback", node.text)


if __name__ == "__main__":
    rospy.init_node("check_bad_input")
    rostest.rosrun("modrob_viz", "check_bad_input", BadInput)
