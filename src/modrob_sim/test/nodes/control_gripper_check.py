#!/usr/bin/env python3
"""rostest node for control_gripper.test: the gripper_cmd action as a pick-and-place client
(or MoveIt's gripper controller handle) uses it."""
import os
import sys
import unittest

import actionlib
import rospy
import rostest
from actionlib_msgs.msg import GoalStatus
from control_msgs.msg import GripperCommandAction, GripperCommandGoal
from gazebo_msgs.srv import GetModelState, SpawnModel
from geometry_msgs.msg import Pose

from modrob_sim import waits
from modrob_sim.waits import wait_running

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from control_common import RosoutCollector, wait_for_action_server  # noqa: E402

NS = "/gripper"


def command(position, max_effort):
    g = GripperCommandGoal()
    g.command.position, g.command.max_effort = position, max_effort
    return g


class GripperAction(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("control_gripper_check")
        cls.rosout = RosoutCollector()
        wait_running(NS, ["joint_state_controller", "gripper_controller"])
        cls.client = actionlib.SimpleActionClient(NS + "/gripper_controller/gripper_cmd",
                                                  GripperCommandAction)
        wait_for_action_server(cls.client, 30, "the gripper_cmd action server")

    def send(self, position, max_effort):
        self.client.send_goal(command(position, max_effort))
        self.assertTrue(waits.wait_for_result(self.client, 60), "no result")
        return self.client.get_state(), self.client.get_result()

    def test_1_closing_on_a_can_stalls(self):
        rospy.wait_for_service("/gazebo/spawn_urdf_model", timeout=30)
        spawn = rospy.ServiceProxy("/gazebo/spawn_urdf_model", SpawnModel)
        res = spawn("can", rospy.get_param("/can_description"), "", Pose(), "world")
        self.assertTrue(res.success, res.status_message)
        state, result = self.send(0.0, 5.0)
        self.assertEqual(state, GoalStatus.ABORTED)
        self.assertTrue(result.stalled)
        self.assertFalse(result.reached_goal)
        self.assertAlmostEqual(result.position, 0.03, delta=0.001)     # the 60 mm can between the pads
        self.assertLess(result.effort, -1.0)                            # pressing on it
        can = rospy.ServiceProxy("/gazebo/get_model_state", GetModelState)("can", "world").pose.position
        self.assertLess(max(abs(can.x), abs(can.y)), 0.002)             # squeezed in place

    def test_2_opening_reaches_the_goal(self):
        state, result = self.send(0.04, 5.0)
        self.assertEqual(state, GoalStatus.SUCCEEDED)
        self.assertTrue(result.reached_goal)
        self.assertFalse(result.stalled)
        self.assertAlmostEqual(result.position, 0.04, delta=0.002)

    def test_3_bad_goals(self):
        state, result = self.send(float("nan"), 5.0)
        self.assertEqual(state, GoalStatus.REJECTED)
        state, result = self.send(0.02, 0.0)                            # ros_controllers: no effort at all
        self.assertEqual(state, GoalStatus.ABORTED)
        self.assertTrue(result.stalled)
        self.rosout.wait_for("max_effort 0", "finger_joint1")


if __name__ == "__main__":
    rostest.rosrun("modrob_sim", "control_gripper", GripperAction)
