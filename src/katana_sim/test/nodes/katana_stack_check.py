#!/usr/bin/env python3
"""rostest node for katana_stack.test: the can stacker in-process, cans from the laser detections;
asserts the stack stands."""
import unittest

import rospy
import rostest

from katana_sim.stack_node import CanStackNode


class KatanaStack(unittest.TestCase):
    def test_top_can_stands_on_the_bottom_can(self):
        rospy.init_node("katana_stack_check")
        rospy.set_param("~source", "detection")   # the laser, the detector, tf: the whole pipeline
        node = CanStackNode()
        ok = node.run()
        self.assertTrue(ok, "the stack does not stand (see the RESULT line above)")
        outcome_top = node.arm.model_pose("coke_can_1")
        self.assertIsNotNone(outcome_top)


if __name__ == "__main__":
    rostest.rosrun("katana_sim", "katana_stack_check", KatanaStack)
