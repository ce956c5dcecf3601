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

from modrob_sim import waits
from modrob_sim.waits import sim_sleep, wait_running, wait_until

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from control_common import Latest, RosoutCollector  # noqa: E402

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
        cls.pub = waits.command_publisher(CTRL + "/command", Float64, 20)
        wait_until(lambda: cls.state.msg is not None and cls.joints.msg is not None, 30, "state and "
                                                                                         "joint_states")

    def position(self, msg=None):
        msg = msg or self.joints.msg
        return msg.position[msg.name.index("shoulder")]

    def step(self, target, settle_time=4.0):
        """Command ``target``; return (rise time to 90 % of the step, the joint's position and the
        controller's state ``settle_time`` later). The rise time is read from the controller's
        state messages (stamped in simulated time, one per 10 ms of it): from the first with the
        new set point to the first at 90 % of the step, so it does not depend on how fast the
        simulation runs against the wall clock. It is None when a message at either end was lost:
        at real_time_factor 0 the publisher's queue (10, as ros_controllers' realtime publisher
        drops too) overflows now and then, and a lost one would shorten or lengthen the time."""
        self.state.clear()
        start_pos = self.position(self.joints.fresh())
        self.pub.publish(Float64(target))
        self.state.wait(lambda m: m.set_point == target, 20, "the command to arrive")
        history = self.state.history
        i0 = next(i for i, m in enumerate(history) if m.set_point == target)
        t0 = history[i0].header.stamp.to_sec()
        settled = self.state.after(t0 + settle_time)
        final = self.position(self.joints.after(t0 + settle_time))
        history = self.state.history
        i90 = next((i for i in range(i0, len(history))
                    if abs(history[i].process_value - start_pos) >= 0.9 * abs(target - start_pos)), None)
        self.assertIsNotNone(i90, "the step to %g did not reach 90 %%" % target)
        stamps = [m.header.stamp.to_sec() for m in history]
        seen = all(i > 0 and stamps[i] - stamps[i - 1] < 0.015 for i in (i0, i90))
        return (stamps[i90] - t0 if seen else None), final, settled

    def rise_time(self, target, back_to, tries=5):
        """The rise time of the step ``back_to`` -> ``target`` (at ``target`` on return), stepping
        again until both ends of the rise were seen."""
        for _ in range(tries):
            rise, final, state = self.step(target)
            if rise is not None:
                return rise, final, state
            rospy.logwarn("a state message at the start of the step or at 90 % was lost: stepping again")
            self.step(back_to)
        self.fail("state messages lost at the ends of the rise in %d steps" % tries)

    def test_1_step_settles_then_higher_p_rises_faster(self):
        rise_slow, final, state = self.rise_time(0.5, back_to=0.0)
        self.assertLess(abs(final - 0.5), 0.01, "settled at %.4f" % final)
        self.assertLess(abs(state.error), 0.01)
        self.assertEqual(state.p, 60.0)
        self.step(0.0)
        client = Client(CTRL + "/pid", timeout=20)
        client.update_configuration({"p": 240.0})
        self.state.wait(lambda m: m.p == 240.0, 20, "the new p in the controller state")
        rise_fast, final, _state = self.rise_time(0.5, back_to=0.0)
        rospy.loginfo("rise time p=60: %.3f s, p=240: %.3f s" % (rise_slow, rise_fast))
        self.assertLess(abs(final - 0.5), 0.01)
        self.assertLess(rise_fast, 0.85 * rise_slow)

    def test_2_nan_is_ignored_with_a_warning(self):
        self.pub.publish(Float64(0.3))
        wait_until(lambda: self.state.msg.set_point == 0.3, 20, "set point 0.3")
        self.pub.publish(Float64(float("nan")))
        self.log.wait_for(CTRL + "/command", "not finite")
        sim_sleep(0.5)
        self.assertEqual(self.state.fresh().set_point, 0.3)
        self.assertTrue(math.isfinite(self.position(self.joints.fresh())))

    def test_3_command_beyond_the_limit_is_clamped(self):
        self.pub.publish(Float64(5.0))
        wait_until(lambda: self.state.msg.set_point == 2.0, 20, "set point clamped to the upper limit 2.0")
        self.log.wait_for(CTRL + "/command", "clamped to 2")
        sim_sleep(3.0)
        self.assertLess(abs(self.position(self.joints.fresh()) - 2.0), 0.02)


if __name__ == "__main__":
    rostest.rosrun("modrob_sim", "control_arm", ArmPositionControl)
