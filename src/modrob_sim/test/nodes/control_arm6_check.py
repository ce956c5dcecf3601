#!/usr/bin/env python3
"""rostest node for control_arm6.test: one arm, three interfaces per joint, controllers switched
with controller_manager's switch_controller service as a user (or MoveIt's controller manager)
does it."""
import os
import sys
import unittest

import actionlib
import rospy
import rostest
from actionlib_msgs.msg import GoalStatus
from control_msgs.msg import (FollowJointTrajectoryAction, FollowJointTrajectoryGoal,
                              FollowJointTrajectoryResult)
from control_msgs.srv import QueryTrajectoryState
from controller_manager_msgs.srv import ListControllers, SwitchController
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64MultiArray
from trajectory_msgs.msg import JointTrajectoryPoint

from modrob_sim import waits
from modrob_sim.waits import controller_states, wait_running, wait_until

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from control_common import Latest, wait_for_action_server  # noqa: E402

NS = "/arm6"
JOINTS = ["shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint", "wrist_1_joint", "wrist_2_joint",
          "wrist_3_joint"]
FIRST = [0.6, -0.7, 1.2, -0.8, 0.5, 0.9]
SECOND = [-0.5, 0.4, -0.9, 1.0, -0.6, -1.2]
THIRD = [0.2, -0.3, 0.5, -0.4, 0.3, 0.4]
STRICT = 2


def goal(positions, seconds=2.0):
    g = FollowJointTrajectoryGoal()
    g.trajectory.joint_names = list(JOINTS)
    g.trajectory.points.append(JointTrajectoryPoint(positions=positions, velocities=[0.0] * 6,
                                                    time_from_start=rospy.Duration(seconds)))
    return g


class ArmWithThreeInterfaces(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("control_arm6_check")
        wait_running(NS, ["joint_state_controller", "eff_joint_traj_controller"])
        wait_until(lambda: controller_states(NS).get("joint_group_eff_controller") == "initialized", 60,
                   "the stopped spawner's controllers")
        cls.switch = rospy.ServiceProxy(NS + "/controller_manager/switch_controller", SwitchController)
        cls.listing = rospy.ServiceProxy(NS + "/controller_manager/list_controllers", ListControllers)
        cls.js = Latest(NS + "/joint_states", JointState)
        wait_until(lambda: cls.js.msg is not None, 30, "joint_states")
        cls.clients = {}

    def client(self, controller):
        if controller not in self.clients:
            c = actionlib.SimpleActionClient("%s/%s/follow_joint_trajectory" % (NS, controller),
                                             FollowJointTrajectoryAction)
            wait_for_action_server(c, 30, "%s's follow_joint_trajectory" % controller)
            self.clients[controller] = c
        return self.clients[controller]

    @staticmethod
    def error(msg, target):
        """Largest |position - target| in the joint_states message ``msg``."""
        pos = dict(zip(msg.name, msg.position))
        return max(abs(pos[j] - q) for j, q in zip(JOINTS, target))

    def error_after(self, target, stamp):
        """``error`` of the first joint_states message stamped at ``stamp`` or later."""
        return self.error(self.js.after(stamp, 30), target)

    def move(self, controller, target):
        c = self.client(controller)
        c.send_goal(goal(target))
        self.assertTrue(waits.wait_for_result(c, 60), "no result from %s" % controller)
        self.assertEqual(c.get_state(), GoalStatus.SUCCEEDED, c.get_result().error_string)
        # from the result's stamp: this node's clock can be a simulated second behind it, mid-motion
        self.assertLess(self.error_after(target, waits.result_time(c)), 0.01)

    def test_1_effort_trajectory_controller_reaches_the_goal(self):
        claimed = {c.name: c.claimed_resources for c in self.listing().controller}
        (res,) = claimed["eff_joint_traj_controller"]
        self.assertEqual(res.hardware_interface, "hardware_interface::EffortJointInterface")
        self.assertEqual(list(res.resources), JOINTS)
        self.assertEqual(claimed["joint_group_pos_controller"][0].hardware_interface,
                         "hardware_interface::PositionJointInterface")
        self.move("eff_joint_traj_controller", FIRST)

    def test_2_out_of_limit_and_unrepresentable_goals_are_refused_by_name(self):
        c = self.client("eff_joint_traj_controller")
        for bad, needle in (([0.0, 0.0, 4.0, 0.0, 0.0, 0.0],
                             "position 4 of joint 'elbow_joint' is outside its limits [-3.14159, 3.14159]"),
                            ([1e308, 0.0, 0.0, 0.0, 0.0, 0.0],
                             "position 1e+308 of joint 'shoulder_pan_joint' is outside its limits")):
            c.send_goal(goal(bad))
            self.assertTrue(waits.wait_for_result(c, 30))
            self.assertEqual(c.get_state(), GoalStatus.REJECTED)
            self.assertEqual(c.get_result().error_code, FollowJointTrajectoryResult.INVALID_GOAL)
            self.assertIn(needle, c.get_result().error_string)
        self.assertLess(self.error_after(FIRST, rospy.get_time()), 0.01)     # still holding

    def test_3_query_state_samples_the_trajectory(self):
        query = rospy.ServiceProxy(NS + "/eff_joint_traj_controller/query_state", QueryTrajectoryState)
        now = rospy.Time.now()
        res = query(now)
        self.assertEqual(list(res.name), JOINTS)
        for q, target in zip(res.position, FIRST):
            self.assertAlmostEqual(q, target, places=6)          # holding the last goal's end
        with self.assertRaises(rospy.ServiceException):
            query(rospy.Time(0.001))                             # before the trajectory's start

    def test_4_a_second_controller_on_the_joints_is_a_resource_conflict(self):
        self.assertFalse(self.switch(["joint_group_pos_controller"], [], STRICT, False, 0.0).ok)
        self.assertEqual(controller_states(NS)["eff_joint_traj_controller"], "running")

    def test_5_switch_to_the_position_group_and_back(self):
        self.assertTrue(self.switch(["joint_group_pos_controller"], ["eff_joint_traj_controller"], STRICT,
                                    False, 0.0).ok)
        self.assertLess(self.error_after(FIRST, rospy.get_time() + 0.2), 0.01)   # holds where it was
        pub = waits.command_publisher(NS + "/joint_group_pos_controller/command", Float64MultiArray, 20)
        pub.publish(Float64MultiArray(data=SECOND))
        stamp = rospy.get_time()
        self.js.wait(lambda m: m.header.stamp.to_sec() >= stamp and self.error(m, SECOND) < 0.01, 30,
                     "the arm at the group command")
        self.assertTrue(self.switch(["eff_joint_traj_controller"], ["joint_group_pos_controller"], STRICT,
                                    False, 0.0).ok)
        self.move("eff_joint_traj_controller", FIRST)

    def test_6_velocity_trajectory_controller(self):
        self.assertTrue(self.switch(["vel_joint_traj_controller"], ["eff_joint_traj_controller"], STRICT,
                                    False, 0.0).ok)
        self.move("vel_joint_traj_controller", THIRD)
        self.assertTrue(self.switch(["eff_joint_traj_controller"], ["vel_joint_traj_controller"], STRICT,
                                    False, 0.0).ok)
        self.move("eff_joint_traj_controller", FIRST)


if __name__ == "__main__":
    rostest.rosrun("modrob_sim", "control_arm6", ArmWithThreeInterfaces)
