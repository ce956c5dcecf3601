#!/usr/bin/env python3
"""rostest node of ptrz_launch.test: ptrz.launch (indoor world, headless) brings the camera up
(controllers, robot_state_publisher's tf at the seed's geometry), and the keyboard teleop, driven
through a pseudo-terminal, sends the seed's command sequence, h brings the camera home, Ctrl-C
restores the terminal and the camera holds its last position."""
import os
import pty
import select
import subprocess
import sys
import termios
import unittest

import rospy
import rostest
import tf2_ros
from std_msgs.msg import Float64

from modrob_sim import waits
from modrob_sim.waits import Latest, sim_sleep, wait_running, wait_until

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ptrz_test_common import CONTROLLERS, Joints  # noqa: E402

NS = "/ptrz"


class LaunchAndTeleop(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("launch_teleop_check")
        wait_running(NS, CONTROLLERS)
        cls.joints = Joints(NS)
        cls.cmd = {j: Latest("%s/%s_position_controller/command" % (NS, j), Float64)
                   for j in ("roll", "pan", "tilt")}
        cls.zoom = Latest(NS + "/zoom", Float64)
        wait_until(lambda: cls.joints.msg is not None, 30, "/ptrz/joint_states")

    def test_1_tf_of_the_camera_link_is_the_seeds_geometry(self):
        buf = tf2_ros.Buffer()
        tf2_ros.TransformListener(buf)

        # a JointPositionController holds the position it started at (ros_controllers' starting()),
        # wherever the arm had sagged to by then: command the seed's pose, all joints at 0
        pubs = [waits.command_publisher("%s/%s_position_controller/command" % (NS, j), Float64, 30)
                for j in ("roll", "pan", "tilt")]
        for p in pubs:
            p.publish(Float64(0.0))

        def at_zero():
            m = self.joints.msg
            return all(abs(q) < 2e-3 for n, q in zip(m.name, m.position) if n in ("roll", "pan", "tilt"))
        wait_until(at_zero, 30, "roll, pan and tilt at 0 on /ptrz/joint_states")
        wait_until(lambda: buf.can_transform("world", "camera", rospy.Time(0)), 30, "tf world -> camera")
        t = buf.lookup_transform("world", "camera", rospy.Time(0)).transform.translation
        # pole 4 m, rigid links 0.5/0.25/0.15 m, box 0.3 m (seed appendix B.1), all joints at 0
        self.assertAlmostEqual(t.x, 0.75, delta=0.01)
        self.assertAlmostEqual(t.y, 0.275, delta=0.01)
        self.assertAlmostEqual(t.z, 3.675, delta=0.01)

    def test_2_teleop_through_a_pseudo_terminal(self):
        master, slave = pty.openpty()
        before = termios.tcgetattr(slave)
        env = dict(os.environ)
        proc = subprocess.Popen(["rosrun", "ptrz_camera", "keyboard_joint_control.py",
                                 "__name:=teleop_under_test"],
                                stdin=slave, stdout=slave, stderr=slave, env=env, close_fds=True)
        output = []

        def read_output():
            while True:
                r, _, _ = select.select([master], [], [], 0)
                if not r:
                    return
                try:
                    output.append(os.read(master, 65536).decode("utf-8", "replace"))
                except OSError:
                    return

        def wait_for_commands(roll, pan, tilt, what):
            def ok():
                read_output()
                vals = [self.cmd[j].msg.data if self.cmd[j].msg else None for j in ("roll", "pan", "tilt")]
                return all(v is not None and abs(v - w) < 1e-9 for v, w in zip(vals, (roll, pan, tilt)))
            wait_until(ok, 30, "commands roll %.3f pan %.3f tilt %.3f after %s" % (roll, pan, tilt, what))

        for latest in self.cmd.values():    # test_1's commands: the teleop's own come next
            latest.msg = None
        try:
            wait_for_commands(0.0, 0.0, 0.0, "start")
            script = [("s", (0.0, 0.1, 0.0)), ("s", (0.0, 0.2, 0.0)), ("s", (0.0, 0.3, 0.0)),
                      ("x", (0.0, 0.3, 0.1)), ("e", (0.0, 0.3, 0.1)), ("s", (0.0, 0.41, 0.1)),
                      ("q", (-0.11, 0.41, 0.1)), ("w", (0.0, 0.41, 0.1)), ("h", (0.0, 0.0, 0.0)),
                      ("a", (0.0, -0.1, 0.0)), ("z", (0.0, -0.1, -0.1))]
            for key, expected in script:
                os.write(master, key.encode())
                wait_for_commands(*expected, what="key %r" % key)
            os.write(master, b"+")
            wait_until(lambda: self.zoom.msg is not None, 20, "a zoom command after '+'")
            self.assertAlmostEqual(self.zoom.msg.data, 1.3962634 / 1.25, places=6)
            wait_until(lambda: abs(self.joints.position("pan") + 0.1) < 0.02
                       and abs(self.joints.position("tilt") + 0.1) < 0.02,
                       60, "the camera at pan -0.1 tilt -0.1")
            os.write(master, b"\x03")
            proc.wait(timeout=20)
            read_output()
        finally:
            if proc.poll() is None:
                proc.kill()
        text = "".join(output)
        self.assertEqual(proc.returncode, 0, text[-2000:])
        self.assertEqual(termios.tcgetattr(slave), before, "terminal settings not restored")
        self.assertIn("Control Your ptrz camera", text)
        self.assertEqual(text.count("Control Your ptrz camera"), 2,
                         "help at start and after 6 presses (h resets)")
        self.assertIn("pan 0.4100", text)
        self.assertIn("step 0.1100", text)
        # the camera holds where it was left: no command after the exit, joints stay put
        last = self.cmd["pan"].msg.data
        sim_sleep(2.0)
        self.assertEqual(self.cmd["pan"].msg.data, last)
        self.assertAlmostEqual(self.joints.position("pan"), -0.1, delta=0.02)
        self.assertAlmostEqual(self.joints.position("tilt"), -0.1, delta=0.02)
        os.close(master)
        os.close(slave)

    def test_3_teleop_without_a_terminal_says_so(self):
        proc = subprocess.run(["rosrun", "ptrz_camera", "keyboard_joint_control.py", "__name:=teleop_no_tty"],
                              stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                              timeout=30,
                              universal_newlines=True)
        self.assertEqual(proc.returncode, 2)
        self.assertIn("needs a terminal", proc.stderr)


if __name__ == "__main__":
    rostest.rosrun("ptrz_camera", "ptrz_launch", LaunchAndTeleop)
