#!/usr/bin/env python3
"""motion_publisher moves the arm; motion_terminal (stdin) moves it, survives bad lines, and an xyz
target is reached within 5 mm (forward kinematics of the measured joints)."""
import math
import subprocess
import sys
import time
import unittest

import numpy as np
import rospy
import rostest
from sensor_msgs.msg import JointState

from modrob_sim import waits

ARM = ["joint%d" % i for i in range(1, 7)]


class MotionInterface(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("bas_motion_check")
        cls.q = {}
        cls.sub = rospy.Subscriber("/modrob0/joint_states", JointState, cls._on_js, queue_size=5)
        cls.pub = rospy.Publisher("/modrob0/motion_command", JointState, queue_size=5)
        deadline = time.time() + 60
        # 6 arm joints + gripper finger 1 (finger 2 is its mimic: no transmission, not on joint_states)
        while time.time() < deadline and (len(cls.q) < 7 or cls.pub.get_num_connections() == 0):
            time.sleep(0.1)
        assert len(cls.q) >= 7, "no /modrob0/joint_states within 60 s"
        assert cls.pub.get_num_connections() > 0, \
            "motion_publisher does not listen on /modrob0/motion_command"

    @classmethod
    def _on_js(cls, msg):
        cls.q.update(zip(msg.name, msg.position))
        cls.stamp = msg.header.stamp.to_sec()

    def measured(self):
        return np.array([self.q[n] for n in ARM])

    def wait_close(self, target, tol, timeout=30.0):
        deadline = time.time() + timeout
        err = float("inf")
        while time.time() < deadline:
            err = float(np.max(np.abs(self.measured() - np.asarray(target))))
            if err < tol:
                return err
            time.sleep(0.05)
        return err

    def terminal(self, lines, timeout=60):
        proc = subprocess.run(["rosrun", "modrob_motion", "motion_terminal", "_linger:=1.0"],
                              input="".join(lines), capture_output=True, text=True, timeout=timeout)
        return proc

    def test_1_motion_publisher_moves_the_arm(self):
        target = [0.2, -0.15, -0.1, 0.2, -0.2, 0.3]
        self.pub.publish(JointState(name=list(reversed(ARM)), position=list(reversed(target))))
        err = self.wait_close(target, 0.02)
        self.assertLess(err, 0.02, "arm did not follow a JointState on /modrob0/motion_command")

    def test_2_terminal_lines_and_bad_lines(self):
        target = [-0.2, 0.1, 0.15, -0.1, 0.25, -0.3]
        proc = self.terminal(["bogus\n", "0.1 nan 3\n", "1 2\n", "#7\n", "9 9 9 9 9 9\n",
                              " ".join("%.3f" % v for v in target) + "\n", "state\n"])
        out = proc.stdout
        self.assertEqual(proc.returncode, 0, proc.stderr)
        self.assertIn("'bogus' is neither a number nor a command", out)
        self.assertIn("'nan' is not a finite number", out)
        self.assertIn("modrob0 has 6 arm joints", out)
        self.assertIn("no robot 7", out)
        self.assertIn("above its upper limit", out)
        self.assertIn("modrob0: joints ->", out)
        err = self.wait_close(target, 0.02)
        self.assertLess(err, 0.02, "terminal joint line not carried out:\n" + out)

    def test_3_xyz_within_5mm(self):
        from modrob_kinematics.kdl_urdf import KinematicChain
        urdf = rospy.get_param("/modrob0/robot_description")
        chain = KinematicChain.from_urdf_string(urdf, tip_link="modrob0_gripper_tcp")
        goal = chain.fk_position([-0.4, -0.3, -0.5, 0.3, -0.6, 0.0])
        proc = self.terminal(["xyz %.4f %.4f %.4f\n" % goal, "xyz 5 5 5\n"])
        self.assertEqual(proc.returncode, 0, proc.stderr)
        self.assertIn("unreachable", proc.stdout)
        # reached and settled: within 5 mm at every look for a simulated second (not passing through)
        dist, since = float("inf"), None

        def settled():
            nonlocal dist, since
            stamp = self.stamp
            dist = math.dist(chain.fk_position(list(self.measured())), goal)
            since = None if dist >= 0.005 else (stamp if since is None else since)
            return since is not None and stamp - since >= 1.0
        self.assertTrue(waits.wait_until(settled, 40),
                        "end effector %.1f mm from the xyz target, not within 5 mm for a simulated "
                        "second\n%s" % (1000 * dist, proc.stdout))


if __name__ == "__main__":
    rostest.rosrun("modrob_motion", "bas_motion", MotionInterface, sys.argv)
