#!/usr/bin/env python3
"""rostest node for teleop_twist_keyboard.test: runs the node on a pseudo-terminal, types keys,
reads /cmd_vel; Ctrl-C must publish a zero twist and leave the terminal as it found it."""
import os
import pty
import subprocess
import termios
import threading
import unittest

import rospy
import rostest
from geometry_msgs.msg import Twist

from modrob_sim.waits import wait_until


class KeyboardTeleop(unittest.TestCase):
    def setUp(self):
        rospy.init_node("keyboard_check", anonymous=True)
        self.lock = threading.Lock()
        self.got = []
        self.sub = rospy.Subscriber("/teleop/cmd_vel", Twist, self._cb, queue_size=100)
        self.master, self.slave = pty.openpty()
        self.before = termios.tcgetattr(self.slave)
        self.out = []
        self.proc = subprocess.Popen(["rosrun", "teleop_twist_keyboard", "teleop_twist_keyboard.py",
                                      "cmd_vel:=/teleop/cmd_vel", "_speed:=0.4", "_turn:=0.8",
                                      "_key_timeout:=0"],
                                     stdin=self.slave, stdout=self.slave, stderr=subprocess.STDOUT)
        threading.Thread(target=self._drain, daemon=True).start()

    def _drain(self):
        while True:
            try:
                data = os.read(self.master, 1024)
            except OSError:
                return
            if not data:
                return
            self.out.append(data.decode(errors="replace"))

    def _cb(self, msg):
        with self.lock:
            self.got.append((msg.linear.x, msg.linear.y, msg.angular.z))

    def tearDown(self):
        if self.proc.poll() is None:
            self.proc.kill()
        os.close(self.master)
        os.close(self.slave)

    def type(self, keys):
        os.write(self.master, keys.encode())

    def test_keys_to_twists_then_ctrl_c(self):
        wait_until(lambda: "Moving around" in "".join(self.out), 30, "the key help on the terminal")
        self.type("i")
        wait_until(lambda: (0.4, 0.0, 0.0) in self.got, 10, "i -> forward 0.4 m/s")
        self.type("j")
        wait_until(lambda: (0.0, 0.0, 0.8) in self.got, 10, "j -> turn left 0.8 rad/s")
        self.type("q")
        wait_until(lambda: any(abs(z - 0.88) < 1e-9 for _x, _y, z in self.got), 10, "q -> 10 % faster")
        self.type("\x03")
        self.assertEqual(self.proc.wait(timeout=20), 0)
        wait_until(lambda: self.got and self.got[-1] == (0.0, 0.0, 0.0), 10, "a zero twist after Ctrl-C")
        self.assertEqual(termios.tcgetattr(self.slave), self.before)     # the terminal restored


if __name__ == "__main__":
    rostest.rosrun("teleop_twist_keyboard", "keyboard_check", KeyboardTeleop)
