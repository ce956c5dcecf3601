#!/usr/bin/env python3
"""rostest node for joy_node.test: starts joy_node on a device path that does not exist yet,
checks it says it waits, creates the device (a named pipe) and writes joystick events into it."""
import os
import shutil
import subprocess
import tempfile
import threading
import unittest

import rospy
import rostest
from rosgraph_msgs.msg import Log
from sensor_msgs.msg import Joy

from modrob_sim.waits import wait_until

from joy.joystick import AXIS, BUTTON, INIT, encode


class JoyNodeDevice(unittest.TestCase):
    def test_waits_for_the_device_then_publishes_its_events(self):
        rospy.init_node("joy_check")
        lock = threading.Lock()
        logs, joys = [], []
        rospy.Subscriber("/rosout", Log, lambda m: logs.append(m.msg), queue_size=100)
        rospy.Subscriber("/joy", Joy, lambda m: joys.append(m), queue_size=100)
        tmp = tempfile.mkdtemp()
        self.addCleanup(shutil.rmtree, tmp, ignore_errors=True)
        dev = os.path.join(tmp, "js0")
        proc = subprocess.Popen(["rosrun", "joy", "joy_node", "_dev:=" + dev, "_deadzone:=0.0",
                                 "_autorepeat_rate:=20"])
        try:
            wait_until(lambda: any("Couldn't open joystick " + dev in m and "retry every second" in m
                                   for m in logs), 30, "joy_node saying it waits for " + dev)
            os.mkfifo(dev)
            with open(dev, "wb", buffering=0) as js:
                # the initial state the kernel sends on open, then the user's input
                js.write(encode(0, BUTTON | INIT, 0) + encode(0, BUTTON | INIT, 5)
                         + encode(0, AXIS | INIT, 1))
                js.write(encode(-32767, AXIS, 1))
                wait_until(lambda: any(m.axes and abs(m.axes[1] - 1.0) < 1e-9 for m in joys), 20,
                           "the stick pushed forward on /joy")
                js.write(encode(1, BUTTON, 5))
                wait_until(lambda: any(len(m.buttons) == 6 and m.buttons[5] == 1 for m in joys), 20,
                           "button 5 on /joy")
                with lock:
                    n = len(joys)
                wait_until(lambda: len(joys) >= n + 5, 10, "autorepeat at 20 Hz")
                self.assertEqual(joys[-1].header.frame_id, dev)
            wait_until(lambda: any("lost unexpectedly" in m for m in logs), 20,
                       "the device going away reported")
        finally:
            proc.terminate()
            proc.wait(timeout=20)


if __name__ == "__main__":
    rostest.rosrun("joy", "joy_check", JoyNodeDevice)
