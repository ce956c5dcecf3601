#!/usr/bin/env python3
"""rostest node for dynparam.test: the ROS wiki's command lines, typed as they are, against the
PTRZ controllers: `rosrun dynamic_reconfigure dynparam list|get|set|dump|load`. The gain that
`set` changes is read back through dynamic_reconfigure's client and in the controller's state
topic; dump then load restores what was dumped. (Each dynparam is a Python start: on a loaded
machine seconds each, so the test runs five.)"""
import ast
import os
import subprocess
import tempfile
import time
import unittest

import rospy
import rostest
from control_msgs.msg import JointControllerState
from dynamic_reconfigure.client import Client

SERVER = "/ptrz/pan_position_controller/pid"


def dynparam(*args, timeout=60):
    """Run `rosrun dynamic_reconfigure dynparam ARGS`; (exit code, stdout, stderr)."""
    proc = subprocess.run(["rosrun", "dynamic_reconfigure", "dynparam"] + list(args), capture_output=True,
                          text=True, timeout=timeout)
    return proc.returncode, proc.stdout, proc.stderr


class Dynparam(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("dynparam_check")
        rospy.wait_for_service(SERVER + "/set_parameters", timeout=60)
        cls.client = Client(SERVER, timeout=30)
        cls.state = None
        cls.sub = rospy.Subscriber("/ptrz/pan_position_controller/state", JointControllerState,
                                   lambda m: setattr(cls, "state", m), queue_size=1)

    def wait(self, pred, timeout, what):
        deadline = time.monotonic() + timeout
        while not pred():
            if time.monotonic() > deadline:
                raise AssertionError("timed out after %.0f s waiting for %s" % (timeout, what))
            time.sleep(0.02)

    def wait_config(self, **expected):
        """Until the client's copy (kept by parameter_updates) shows ``expected``."""
        self.wait(lambda: all((self.client.get_configuration(timeout=5) or {}).get(k) == v
                              for k, v in expected.items()), 30, "server config %s" % expected)

    def run_ok(self, *args):
        code, out, err = dynparam(*args)
        self.assertEqual(code, 0, "dynparam %s failed (%d): %s%s" % (" ".join(args), code, out, err))
        return out

    def test_1_list_names_the_three_servers(self):
        out = self.run_ok("list").split()
        for c in ("pan", "tilt", "roll"):
            self.assertIn("/ptrz/%s_position_controller/pid" % c, out)

    def test_2_set_p_200_changes_the_gain(self):
        self.run_ok("set", SERVER, "p", "200")
        self.wait_config(p=200.0)
        self.wait(lambda: self.state is not None and self.state.p == 200.0, 30,
                  "p = 200 in the controller state")
        got = ast.literal_eval(self.run_ok("get", SERVER))
        self.assertEqual(got["p"], 200.0)

    def test_3_dump_load_round_trip(self):
        # the values around dump/load are set through the client: one dynparam process less each
        # (a Python start costs seconds on a loaded machine)
        self.assertEqual(self.client.update_configuration({"p": 150.0, "d": 20.0, "i": 0.5})["p"], 150.0)
        self.wait_config(p=150.0, d=20.0, i=0.5)
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "pan_pid.yaml")
            self.run_ok("dump", SERVER, path)
            self.assertTrue(os.path.getsize(path) > 0)
            self.assertEqual(self.client.update_configuration({"p": 10.0, "d": 1.0, "i": 0.0})["p"], 10.0)
            self.wait_config(p=10.0, d=1.0, i=0.0)
            self.run_ok("load", SERVER, path)
        self.wait_config(p=150.0, d=20.0, i=0.5)
        self.wait(lambda: self.state.p == 150.0 and self.state.d == 20.0, 30,
                  "loaded gains in the controller")


if __name__ == "__main__":
    rostest.rosrun("rqt_reconfigure", "dynparam_check", Dynparam)
