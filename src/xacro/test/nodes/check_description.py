#!/usr/bin/env python3
"""The descriptions that $(find xacro)/xacro and xacro.py wrote are expanded URDF."""
import unittest
import xml.etree.ElementTree as ET

import rospy
import rostest


class FindXacro(unittest.TestCase):
    def _robot(self, param):
        text = rospy.get_param(param)
        root = ET.fromstring(text)
        self.assertEqual(root.tag, "robot")
        self.assertEqual(root.get("name"), "xacro_arm")
        return root

    def test_xacro(self):
        root = self._robot("/robot_description")
        self.assertEqual(sorted(ln.get("name") for ln in root.findall("link")), ["base", "upper"])
        self.assertEqual(root.find("joint/origin").get("xyz"), "0 0 0.7")  # the launch argument
        text = ET.tostring(root).decode()
        self.assertNotIn("xacro:", text)  # every macro expanded
        self.assertNotIn("${", text)

    def test_xacro_py(self):
        root = self._robot("/robot_description_py")
        self.assertEqual(root.find("joint/origin").get("xyz"), "0 0 0.3")


if __name__ == "__main__":
    rospy.init_node("check_description", anonymous=True)
    rostest.rosrun("xacro", "find_xacro", FindXacro)
