#!/usr/bin/env python3
"""rostest node for control_arm.test: a 0.5 rad step settles within 0.01 rad; raising p through
dynamic_reconfigure (as rqt_reconfigure does) shortens the rise time; NaN commands are ignored
with a warning; a command beyond the joint limit is clamped."""
import math
import os
import sys
import unittest

import rospy
import rostest
from control_msgs.msg import JointControllerState
from dynamic_reconfigure.client import Client
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from control_common import (Latest, RosoutCollector, command_publisher, sim_sleep, wait_running,  # noqa: E402
                            wait_until)

NS = "/arm1"
CTRL = NS + "/shoulder_controller"


class ArmPositionControl(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("control_arm_check")
        cls.log = RosoutCollector()
        wait_running(NS, ["joint_state_controller", "shoulder_controller"])
        cls.state = Latest(CTRL + "/state", JointControllerState)
        cls.joints = Latest(NS + "/joint_states", JointState)
        cls.pub = command_publisher(CTRL + "/command", Float64)
        wait_until(lambda: cls.state.msg is not None and cls.joints.msg is not None, 30, "state and "
                                                                                         "joint_states")

    def position(self):
        return self.joints.msg.position[self.joints.msg.name.index("shoulder")]

    def step(self, target, settle_time=4.0):
        """Command ``target`` and return (rise time to 90 % of the step, final position). The rise
        time is read from the controller's state messages (stamped in simulated time, every 10 ms
        of it): from the first one with the new set point to the first at 90 % of the step, so it
        does not depend on how fast the simulation runs against the wall clock."""
        start_pos = self.position()
        n0 = len(self.state.history)
        self.pub.publish(Float64(target))
        wait_until(lambda: self.state.msg.set_point == target, 20, "the command to arrive")
        sim_sleep(settle_time)
        states = [m for m in self.state.history[n0:] if m.set_point == target]
        t0 = states[0].header.stamp.to_sec()
        rise = next((m.header.stamp.to_sec() - t0 for m in states
                     if abs(m.process_value - start_pos) >= 0.9 * abs(target - start_pos)), None)
        self.assertIsNotNone(rise, "the step to %g did not reach 90 %%" % target)
        return rise, self.position()

    def test_1_step_settles_then_higher_p_rises_faster(self):
        rise_slow, final = self.step(0.5)
        self.assertLess(abs(final - 0.5), 0.01, "settled at %.4f" % final)
        self.assertLess(abs(self.state.msg.error), 0.01)
        self.assertEqual(self.state.msg.p, 60.0)
        self.step(0.0)
        client = Client(CTRL + "/pid", timeout=20)
        client.update_configuration({"p": 240.0})
        wait_until(lambda: self.state.msg.p == 240.0, 20, "the new p in the controller state")
        rise_fast, final = self.step(0.5)
        rospy.loginfo("rise time p=60: %.3f s, p=240: %.3f s" % (rise_slow, rise_fast))
        self.assertLess(abs(final - 0.5), 0.01)
        self.assertLess(rise_fast, 0.85 * rise_slow)

    def test_2_nan_is_ignored_with_a_warning(self):
        self.pub.publish(Float64(0.3))
        wait_until(lambda: self.state.msg.set_point == 0.3, 20, "set point 0.3")
        self.pub.publish(Float64(float("nan")))
        self.log.wait_for(CTRL + "/command", "not finite")
        sim_sleep(0.5)
        self.assertEqual(self.state.msg.set_point, 0.3)
        self.assertTrue(math.isfinite(self.position()))

    def test_3_command_beyond_the_limit_is_clamped(self):
        self.pub.publish(Float64(5.0))
        wait_until(lambda: self.state.msg.set_point == 2.0, 20, "set point clamped to the upper limit 2.0")
        self.log.wait_for(CTRL + "/command", "clamped to 2")
        sim_sleep(3.0)
        self.assertLess(abs(self.position() - 2.0), 0.02)


if __name__ == "__main__":
    rostest.rosrun("modrob_sim", "control_arm", ArmPositionControl)
