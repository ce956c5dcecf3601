#!/usr/bin/env python3
"""rostest node of scanner.test: scanner_joint_control.py _joints:=tilt commands positions in
[0, pi + step], turning at both ends, one step (0.05 rad) per 0.05 s of simulated time, and the
tilt joint follows."""
import math
import os
import sys
import unittest

import rospy
import rostest
from std_msgs.msg import Float64

from modrob_sim import waits
from modrob_sim.waits import wait_running, wait_until

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ptrz_test_common import CONTROLLERS, Joints  # noqa: E402

NS = "/ptrz"
STEP = 0.05


class ScannerBounds(unittest.TestCase):
    def test_scanner_goes_back_and_forth_between_0_and_pi(self):
        rospy.init_node("scanner_check")
        wait_running(NS, CONTROLLERS)
        joints = Joints(NS)
        cmd = waits.Latest(NS + "/tilt_position_controller/command", Float64, keep=True)
        pan = waits.Latest(NS + "/pan_position_controller/command", Float64)

        def values():
            return [m.data for m in cmd.history]

        # up to pi (63 steps), down to 0, up again: a bit more than 1.5 cycles
        wait_until(lambda: len(values()) > 63 * 3 + 5, 85, "1.5 scan cycles of tilt commands")
        v = values()
        self.assertGreaterEqual(min(v), 0.0)
        self.assertLessEqual(max(v), math.pi + STEP)
        self.assertGreaterEqual(max(v), math.pi)
        steps = [b - a for a, b in zip(v, v[1:])]
        self.assertTrue(all(abs(abs(s) - STEP) < 1e-9 for s in steps), "every step is 0.05 rad")
        # the scan may be anywhere when the check subscribes: judge every turning point by the
        # direction it ends (up -> a top at pi .. pi + step, down -> a bottom at 0)
        turns = [i for i in range(1, len(steps)) if (steps[i] > 0) != (steps[i - 1] > 0)]
        tops = [v[i] for i in turns if steps[i - 1] > 0]
        bottoms = [v[i] for i in turns if steps[i - 1] < 0]
        self.assertTrue(tops and bottoms, "turned at both ends (turning points %s)" % [v[i] for i in turns])
        for top in tops:
            self.assertGreaterEqual(top, math.pi)
        for bottom in bottoms:
            self.assertAlmostEqual(bottom, 0.0, places=9)
        times = [t for t, _ in cmd.received]      # a command has no stamp: when it came
        period = (times[-1] - times[0]) / (len(times) - 1)
        self.assertAlmostEqual(period, 0.05, delta=0.02, msg="one step per 0.05 s of simulated time")
        tilts = [m.position[m.name.index("tilt")] for m in joints.history]
        self.assertGreater(max(tilts), 2.9, "the tilt joint followed the scan up")
        self.assertIsNone(pan.msg, "only the chosen joint is commanded")


if __name__ == "__main__":
    rostest.rosrun("ptrz_camera", "scanner", ScannerBounds)
