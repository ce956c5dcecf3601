#!/usr/bin/env python3
"""rostest node for spawner.test: the controllers run, and `rosrun controller_manager
controller_manager list` reports them."""
import subprocess
import time
import unittest

import rospy
import rostest
from controller_manager_msgs.srv import ListControllers


class Spawner(unittest.TestCase):
    def test_controllers_started_by_the_controller_manager_package(self):
        rospy.init_node("spawner_check")
        rospy.wait_for_service("/controller_manager/list_controllers", timeout=60)
        listing = rospy.ServiceProxy("/controller_manager/list_controllers", ListControllers)
        end = time.monotonic() + 60
        states = {}
        while time.monotonic() < end:
            states = {c.name: c.state for c in listing().controller}
            if states.get("diffbot_velocity_controller") == "running" and \
                    states.get("diffbot_joint_publisher") == "running":
                break
            time.sleep(0.1)
        self.assertEqual(states, {"diffbot_joint_publisher": "running",
                                  "diffbot_velocity_controller": "running"})
        out = subprocess.run(["rosrun", "controller_manager", "controller_manager", "list"],
                             capture_output=True, text=True, timeout=60)
        self.assertEqual(out.returncode, 0, out.stderr)
        self.assertIn("diffbot_velocity_controller", out.stdout)


if __name__ == "__main__":
    rostest.rosrun("controller_manager", "spawner_check", Spawner)
