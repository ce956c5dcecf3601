#!/usr/bin/env python3
"""rostest node: robot definitions arrive on the parameter server and the latched topics.

~robots: expected number of robots; ~min_distance: every pair of bases at least this far apart
in x-y; ~gripper: whether the gripper joints must be present; ~out_dir: if set, the generated
files must exist there.
"""
import itertools
import math
import os
import shutil
import unittest
import xml.etree.ElementTree as ET

import rospy
import rostest
import yaml
from std_msgs.msg import String


def wait_for_param(name, timeout=30.0):
    deadline = rospy.Time.now() + rospy.Duration(timeout)
    while not rospy.is_shutdown() and rospy.Time.now() < deadline:
        if rospy.has_param(name):
            return rospy.get_param(name)
        rospy.sleep(0.05)
    raise AssertionError("parameter %s not set within %.0f s" % (name, timeout))


class DescriptionCheck(unittest.TestCase):
    def test_params_and_topics(self):
        n = rospy.get_param("~robots")
        robots = wait_for_param("/modrob_robots")
        self.assertEqual([r["name"] for r in robots], ["modrob%d" % i for i in range(n)])
        for r in robots:
            urdf = wait_for_param("%s/robot_description" % r["namespace"])
            root = ET.fromstring(urdf)
            self.assertEqual(root.get("name"), r["name"])
            prismatic = [j for j in root.findall("joint") if j.get("type") == "prismatic"]
            self.assertEqual(len(prismatic), 2 if rospy.get_param("~gripper") else 0)
            msg = rospy.wait_for_message("%s/robot_description" % r["namespace"], String, timeout=20)
            self.assertEqual(msg.data, urdf)
        d_min = rospy.get_param("~min_distance", 0.0)
        for a, b in itertools.combinations(robots, 2):
            self.assertGreaterEqual(math.hypot(a["base"][0] - b["base"][0], a["base"][1] - b["base"][1]),
                                    d_min - 1e-6)
        manifest = yaml.safe_load(rospy.wait_for_message("/modrob_robots", String, timeout=20).data)
        self.assertEqual(len(manifest["robots"]), n)
        out_dir = rospy.get_param("~out_dir", "")
        if out_dir:
            for name in ["modrob_spawn.launch", "modrob_robots.launch"] + \
                    ["modrob%d.urdf" % i for i in range(n)]:
                self.assertTrue(os.path.isfile(os.path.join(out_dir, name)), name)
            if rospy.get_param("~remove_out_dir", False):
                shutil.rmtree(out_dir)


if __name__ == "__main__":
    rospy.init_node("description_check")
    rostest.rosrun("modrob_build", "description_check", DescriptionCheck)
