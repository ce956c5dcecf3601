#!/usr/bin/env python3
"""rostest node for twist_mux.test: the joystick beats the external command while it is fresh,
the external command comes back 0.5 s after the joystick stops, e_stop silences everything."""
import threading
import time
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import Twist
from std_msgs.msg import Bool

from modrob_sim.waits import wait_until


class Source(object):
    """A teleop-like publisher of one twist (linear.x = tag) at 20 Hz while on."""

    def __init__(self, topic, tag):
        self.pub = rospy.Publisher(topic, Twist, queue_size=1)
        self.msg = Twist()
        self.msg.linear.x = tag
        self.on = threading.Event()
        threading.Thread(target=self._run, daemon=True).start()

    def _run(self):
        while not rospy.is_shutdown():
            if self.on.is_set():
                self.pub.publish(self.msg)
            time.sleep(0.05)


class TwistMuxCheck(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("twist_mux_check")
        cls.lock = threading.Lock()
        cls.out = []
        rospy.Subscriber("base_controller/cmd_vel", Twist, cls._cb, queue_size=100)
        cls.joy = Source("joy_teleop/cmd_vel", 10.0)
        cls.ext = Source("cmd_vel", 1.0)
        cls.estop = rospy.Publisher("e_stop", Bool, queue_size=1, latch=True)
        for p in (cls.joy.pub, cls.ext.pub, cls.estop):
            wait_until(lambda: p.get_num_connections() > 0, 20,
                       "twist_mux subscribing to %s" % p.resolved_name)

    @classmethod
    def _cb(cls, msg):
        with cls.lock:
            cls.out.append((time.monotonic(), msg.linear.x))

    def since(self, t):
        with self.lock:
            return [v for s, v in self.out if s >= t]

    def test_priorities_timeout_and_lock(self):
        self.ext.on.set()
        t = time.monotonic()
        wait_until(lambda: 1.0 in self.since(t), 10, "the external command on the output")
        self.joy.on.set()
        wait_until(lambda: 10.0 in self.since(t), 10, "the joystick on the output")
        t_joy = time.monotonic() + 0.1
        time.sleep(1.0)
        self.assertEqual(set(self.since(t_joy)), {10.0})        # only the joystick while it is fresh
        self.joy.on.clear()
        t_stop = time.monotonic()
        wait_until(lambda: 1.0 in self.since(t_stop), 10, "the external command after the joystick's timeout")
        first_ext = min(s for s, v in self.out if s >= t_stop and v == 1.0)
        self.assertGreater(first_ext - t_stop, 0.35)      # not before the 0.5 s timeout (less a period)
        self.estop.publish(Bool(True))
        diag = []
        sub = rospy.Subscriber("/diagnostics", DiagnosticArray, diag.append, queue_size=10)

        def locked_in_diagnostics():
            values = {kv.key: kv.value for m in diag for s in m.status for kv in s.values}
            return (values.get("lock e_stop", "").startswith("locked")
                    and values.get("current priority") == "255")
        wait_until(locked_in_diagnostics, 10, "/diagnostics reporting e_stop locked")
        sub.unregister()
        time.sleep(0.3)
        t_lock = time.monotonic()
        time.sleep(0.8)
        self.assertEqual(self.since(t_lock), [])                  # e_stop (255) masks every input
        self.estop.publish(Bool(False))
        t_free = time.monotonic()
        wait_until(lambda: 1.0 in self.since(t_free), 10, "the external command after e_stop is released")
        self.ext.on.clear()


if __name__ == "__main__":
    rostest.rosrun("twist_mux", "twist_mux_check", TwistMuxCheck)
