#!/usr/bin/env python3
"""Close the gripper on the bulb at the red tip, lift it clear of the slides, then swing ``~joints``
sinusoidally (``~amplitude`` rad at ``~freq`` Hz) for ``~seconds`` s.

The bulb must stay in the gripper (within 30 mm of the grasp centre; ``~must_hold``), the fingers
press with the grip force, /gazebo reports no blow-up, and the arm really swung: each shaken joint's
measured swing is at least ``~min_swing_share`` of the commanded amplitude (so a sluggish arm cannot
pass the test by not shaking)."""
import sys
import unittest

import rospy
import rostest
from std_msgs.msg import String

from modrob_sim.bulbs_and_slides.layout import Layout
from modrob_sim.bulbs_and_slides.scenario import Scenario


class GraspSanity(unittest.TestCase):
    def test_shaking_does_not_drop_the_bulb(self):
        rospy.init_node("bas_grasp_check")
        force = float(rospy.get_param("~grip_force", 3.0))
        joints = rospy.get_param("~joints", ["joint4", "joint6"])
        amplitude = float(rospy.get_param("~amplitude", 0.25))
        freq = float(rospy.get_param("~freq", 1.0))
        seconds = float(rospy.get_param("~seconds", 5.0))
        events = []
        rospy.Subscriber("/gazebo/guard_events", String, lambda m: events.append(m.data))
        sc = Scenario(Layout.load("one_robot"), log=rospy.loginfo)
        held, worst, effort, swing = sc.grasp_and_shake(seconds=seconds, amplitude=amplitude, freq=freq,
                                                        joints=tuple(joints))
        if rospy.get_param("~must_hold", True):
            self.assertTrue(held, "the bulb left the gripper while shaking (%.1f mm from the grasp centre)"
                            % (1000 * worst))
        pose = sc.world.pose("bulb_0")
        self.assertTrue(pose is not None and 0.9 < pose[0][2] < 2.0 and abs(pose[0][0]) < 1.1
                        and abs(pose[0][1]) < 0.7, "bulb_0 left the table: %r" % (pose,))
        self.assertAlmostEqual(effort, force, delta=0.15 * force,
                               msg="fingers press with %.2f N, the grip force is %.1f N" % (effort, force))
        share = float(rospy.get_param("~min_swing_share", 0.7))
        for j in joints:
            got = swing.get(j, 0.0)
            self.assertGreater(got, share * amplitude,
                               "%s swung only %.3f rad of the commanded %.2f" % (j, got, amplitude))
        self.assertEqual(events, [], "the simulator reported blow-ups: %s" % events)


if __name__ == "__main__":
    rostest.rosrun("modrob_sim", "bas_grasp", GraspSanity, sys.argv)
