#!/usr/bin/env python3
"""rostest node of seed_motion.test: seed 002's own xacro and YAML (unchanged) spawn, the
controllers come up under /ptrz, pan/tilt/roll reach commanded angles within 0.02 rad, and a
continuous joint takes the short way (pan 0.1 -> 6.2 rad turns through 0, not through pi)."""
import math
import os
import sys
import unittest

import rospy
import rostest
from std_msgs.msg import Float64

from modrob_sim.waits import sim_sleep, wait_running, wait_until

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ptrz_test_common import CONTROLLERS, Joints  # noqa: E402

NS = "/ptrz"
TOL = 0.02


def angle_error(a, b):
    return math.atan2(math.sin(a - b), math.cos(a - b))


class SeedMotion(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("seed_motion_check")
        wait_running(NS, CONTROLLERS)
        cls.joints = Joints(NS)
        cls.pubs = {j: rospy.Publisher("%s/%s_position_controller/command" % (NS, j), Float64, queue_size=1,
                                       latch=True) for j in ("pan", "tilt", "roll")}
        wait_until(lambda: cls.joints.msg is not None, 30, "/ptrz/joint_states")

    def velocity(self, joint):
        msg = self.joints.msg
        return msg.velocity[msg.name.index(joint)]

    def move(self, targets, settle=4.0, wall_timeout=60):
        for j, v in targets.items():
            self.pubs[j].publish(Float64(v))
        t0 = rospy.get_time()
        wait_until(lambda: all(abs(angle_error(self.joints.position(j), v)) < TOL
                               and abs(self.velocity(j)) < 0.01
                               for j, v in targets.items()),
                   wall_timeout, "joints %s to settle at %s" % (list(targets), targets))
        sim_sleep(0.5)   # and stay there
        for j, v in targets.items():
            err = angle_error(self.joints.position(j), v)
            self.assertLess(abs(err), TOL, "%s at %.4f, commanded %.4f" % (j, self.joints.position(j), v))
        return t0

    def test_1_each_joint_reaches_its_target(self):
        self.move({"pan": 0.7, "tilt": 0.5, "roll": -0.4})
        self.move({"pan": -1.2, "tilt": 1.0, "roll": 0.9})
        self.move({"pan": 0.0, "tilt": 0.0, "roll": 0.0})

    def test_2_continuous_joint_takes_the_short_way(self):
        self.move({"pan": 0.1})
        t0 = self.move({"pan": 6.2})
        path = self.joints.positions_since("pan", t0)
        self.assertLess(max(path), 0.1 + TOL, "pan went up from 0.1 (long way round): max %.3f" % max(path))
        self.assertLess(min(path), 0.0, "pan did not pass through 0")
        self.assertGreater(min(path), 6.2 - 2 * math.pi - 0.1, "pan overshot far past 6.2 - 2 pi")
        self.assertAlmostEqual(self.joints.position("pan"), 6.2 - 2 * math.pi, delta=TOL)


if __name__ == "__main__":
    rostest.rosrun("ptrz_camera", "seed_motion", SeedMotion)
