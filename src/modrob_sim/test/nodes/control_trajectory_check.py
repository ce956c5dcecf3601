#!/usr/bin/env python3
"""rostest node for control_trajectory.test: the FollowJointTrajectory action as a MoveIt-style
client uses it (actionlib.SimpleActionClient, control_msgs.msg.FollowJointTrajectoryAction)."""
import os
import sys
import unittest

import actionlib
import rospy
import rostest
from actionlib_msgs.msg import GoalStatus, GoalStatusArray
from gazebo_msgs.srv import GetPhysicsProperties, GetWorldProperties
from std_srvs.srv import Empty
from rosgraph_msgs.msg import Log
from control_msgs.msg import (FollowJointTrajectoryAction, FollowJointTrajectoryGoal,
                              FollowJointTrajectoryResult, JointTrajectoryControllerState)
from trajectory_msgs.msg import JointTrajectoryPoint

from modrob_sim import waits
from modrob_sim.waits import wait_running, wait_until

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from control_common import Latest, wait_for_action_server  # noqa: E402

NS = "/arm3"
JOINTS = ["yaw", "shoulder", "elbow"]


def goal(points, joints=JOINTS):
    g = FollowJointTrajectoryGoal()
    g.trajectory.joint_names = list(joints)
    for positions, t in points:
        p = JointTrajectoryPoint(positions=positions, time_from_start=rospy.Duration(t))
        g.trajectory.points.append(p)
    return g


class FollowJointTrajectory(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("control_trajectory_check")
        wait_running(NS, ["joint_state_controller", "arm_controller"])
        cls.client = actionlib.SimpleActionClient(NS + "/arm_controller/follow_joint_trajectory",
                                                  FollowJointTrajectoryAction)
        wait_for_action_server(cls.client, 30, "the follow_joint_trajectory action server")
        cls.state = Latest(NS + "/arm_controller/state", JointTrajectoryControllerState)
        wait_until(lambda: cls.state.msg is not None, 30, "the controller state")

    def test_1_three_point_goal_succeeds_within_tolerance(self):
        g = goal([([0.3, 0.2, -0.3], 1.0), ([0.6, 0.5, -0.6], 2.0), ([0.4, 0.3, -0.2], 3.0)])
        self.client.send_goal(g)
        self.assertTrue(waits.wait_for_result(self.client, 60), "no result")
        res = self.client.get_result()
        self.assertEqual(self.client.get_state(), GoalStatus.SUCCEEDED, res.error_string)
        self.assertEqual(res.error_code, FollowJointTrajectoryResult.SUCCESSFUL)
        # a state from after the result: the result message's stamp is the simulated time it was
        # decided at (this node's /clock can be a little behind the result it has just received)
        state = self.state.after(waits.result_time(self.client), 10)
        for name, target, actual in zip(state.joint_names, [0.4, 0.3, -0.2], state.actual.positions):
            self.assertLess(abs(actual - target), 0.02, "%s at %.4f, goal %.4f" % (name, actual, target))

    def test_2_unknown_joint_is_rejected_by_name(self):
        self.client.send_goal(goal([([0.1, 0.1, 0.1], 1.0)], joints=["yaw", "shoulder", "wrist_roll"]))
        self.assertTrue(waits.wait_for_result(self.client, 30))
        self.assertEqual(self.client.get_state(), GoalStatus.REJECTED)
        res = self.client.get_result()
        self.assertEqual(res.error_code, FollowJointTrajectoryResult.INVALID_JOINTS)
        self.assertIn("wrist_roll", res.error_string)

    def test_3_new_goal_preempts_the_old(self):
        first = actionlib.SimpleActionClient(NS + "/arm_controller/follow_joint_trajectory",
                                             FollowJointTrajectoryAction)
        wait_for_action_server(first, 30, "the follow_joint_trajectory action server (second client)")
        first.send_goal(goal([([-0.5, 0.4, -0.4], 3.0)]))
        wait_until(lambda: first.get_state() == GoalStatus.ACTIVE, 30, "the first goal to be active")
        self.client.send_goal(goal([([0.0, 0.1, 0.0], 1.5)]))
        self.assertTrue(waits.wait_for_result(first, 30))
        self.assertEqual(first.get_state(), GoalStatus.PREEMPTED)
        self.assertTrue(waits.wait_for_result(self.client, 60))
        self.assertEqual(self.client.get_state(), GoalStatus.SUCCEEDED, self.client.get_result().error_string)

    def test_4_a_100k_point_goal_is_built_off_the_loop_thread(self):
        """The node answers services while it builds a 100k-point goal: a request sent once the
        action callback has started on the goal (its log line) is answered at a simulated time
        before the goal's acceptance. Built in the loop thread, the loop answered it only
        afterwards."""
        seen = {"building": False, "active_stamp": None}
        gid = []

        def on_status(msg):
            for st in msg.status_list:
                if gid and st.goal_id.id == gid[0] and st.status == GoalStatus.ACTIVE:
                    t = msg.header.stamp.to_sec()
                    if seen["active_stamp"] is None or t < seen["active_stamp"]:
                        seen["active_stamp"] = t

        def on_log(msg):
            if "100000-point trajectory" in msg.msg:
                seen["building"] = True
        subs = [rospy.Subscriber(NS + "/arm_controller/follow_joint_trajectory/status", GoalStatusArray,
                                 on_status, queue_size=50),
                rospy.Subscriber("/rosout", Log, on_log, queue_size=100)]
        world = rospy.ServiceProxy("/gazebo/get_world_properties", GetWorldProperties)
        physics = rospy.ServiceProxy("/gazebo/get_physics_properties", GetPhysicsProperties)
        world.wait_for_service(30)
        here = list(self.state.msg.desired.positions)
        n = 100000
        g = FollowJointTrajectoryGoal()
        g.trajectory.joint_names = list(JOINTS)
        g.trajectory.points = [JointTrajectoryPoint(positions=[q + 1e-7 * i for q in here],
                                                    time_from_start=rospy.Duration(0.5 + 0.001 * i))
                               for i in range(n)]
        self.client.send_goal(g)
        gid.append(self.client.gh.comm_state_machine.action_goal.goal_id.id)
        wait_until(lambda: seen["building"], 60, "the controller to start building the goal")
        self.assertIsNone(seen["active_stamp"], "accepted before the build was announced")
        answered_at = world().sim_time
        self.assertGreater(physics().time_step, 0.0)
        wait_until(lambda: seen["active_stamp"] is not None, 60, "the 100k-point goal to be accepted")
        for sub in subs:
            sub.unregister()
        self.assertLess(answered_at, seen["active_stamp"],
                        "the service was answered only after the goal was built (sim time %.3f, goal "
                        "active at %.3f): the build blocked the loop" % (answered_at, seen["active_stamp"]))
        self.client.cancel_goal()
        self.assertTrue(waits.wait_for_result(self.client, 30))
        self.assertEqual(self.client.get_state(), GoalStatus.PREEMPTED)

    def test_5_the_goal_status_comes_at_5_hz_of_simulated_time_also_after_a_reset(self):
        """actionlib's status array, every 0.2 s of simulated time (its status_frequency), goes on
        after reset_simulation sends the clock back to 0. rospy's Timer, which actionlib uses for
        it, ends its thread when time moves backwards."""
        stamps = []
        sub = rospy.Subscriber(NS + "/arm_controller/follow_joint_trajectory/status", GoalStatusArray,
                               lambda m: stamps.append(m.header.stamp.to_sec()), queue_size=100)
        wait_until(lambda: len(stamps) >= 8, 30, "8 status arrays")
        before = list(stamps)
        # the first is the latched one; goal transitions (the previous test's cancel) add their own.
        # The timer's thread wakes when the simulation loop has set the node's time past its next
        # period, which on a loaded machine, at real_time_factor 0, may be tens of ms of simulated
        # time late (stamps 0.24, 0.13, 0.26 s apart): its schedule is kept, so the stamps are
        # 0.2 s apart in the middle and none a period late
        gaps = [b - a for a, b in zip(before[1:], before[2:])]
        self.assertAlmostEqual(sorted(gaps)[len(gaps) // 2], 0.2, delta=0.05, msg="status stamps %s" % before)
        self.assertLess(max(gaps), 0.35, "status stamps %s" % before)
        reset = rospy.ServiceProxy("/gazebo/reset_simulation", Empty)
        reset.wait_for_service(30)
        reset()
        del stamps[:]
        wait_until(lambda: len([t for t in stamps if t < before[-1]]) >= 4, 30,
                   "4 status arrays stamped after the reset")
        sub.unregister()
        # a client made after the reset finds the server (actionlib's wait_for_server waits for a
        # status array)
        client = actionlib.SimpleActionClient(NS + "/arm_controller/follow_joint_trajectory",
                                              FollowJointTrajectoryAction)
        wait_for_action_server(client, 30, "the action server, from a client made after the reset")


if __name__ == "__main__":
    rostest.rosrun("modrob_sim", "control_trajectory", FollowJointTrajectory)
