#!/usr/bin/env python3
"""rostest node for katana_arm.test: a katana_driver-style client of the arm and gripper actions."""
import math
import os
import subprocess
import termios
import time
import unittest

import actionlib
import rospy
import rostest
from actionlib_msgs.msg import GoalStatus
from control_msgs.msg import (FollowJointTrajectoryAction, FollowJointTrajectoryGoal, GripperCommandAction,
                              GripperCommandGoal)
from sensor_msgs.msg import JointState
from trajectory_msgs.msg import JointTrajectoryPoint

import numpy as np
from gazebo_msgs.msg import LinkStates, ModelState
from gazebo_msgs.srv import GetWorldProperties, SetModelState
from geometry_msgs.msg import PoseArray, PoseStamped

from katana_sim import kinematics as kin
from katana_sim.kinematics import JOINTS
from katana_sim.srv import GetFK, GetIK
from modrob_sim import waits

TOLERANCE = 0.05  # katana_arm_controller's goal tolerance (rad)
PERIOD = 0.02     # joint_state_controller's publish_rate 50


class KatanaArm(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("katana_arm_check")
        cls.joints = waits.Latest("/joint_states", JointState, keep=True)
        cls.detections = None
        rospy.Subscriber("/katana/detected_objects", PoseArray, cls._detections)
        cls.arm = actionlib.SimpleActionClient("/katana_arm_controller/follow_joint_trajectory",
                                               FollowJointTrajectoryAction)
        cls.gripper = actionlib.SimpleActionClient("/gripper_grasp_posture_controller", GripperCommandAction)
        # in wall time: actionlib's timeout is simulated time, which at real_time_factor 0 ran out
        # 0.4 s after start, before the spawner had started the controllers
        missing = waits.wait_for_action_servers(
            ((cls.arm, "/katana_arm_controller/follow_joint_trajectory"),
             (cls.gripper, "/gripper_grasp_posture_controller")), 60)
        assert missing is None, "no %s" % missing
        cls.joints.wait(lambda m: all(j in m.name for j in JOINTS + ("katana_r_finger_joint",)), 30,
                        "joint states of the arm and the fingers")

    @classmethod
    def _detections(cls, msg):
        cls.detections = msg

    def positions(self, msg=None):
        """{joint: position} of ``msg`` (default: the latest /joint_states)."""
        msg = msg or self.joints.msg
        return dict(zip(msg.name, msg.position))

    def positions_after(self, client):
        """The joint positions in the first /joint_states stamped when ``client``'s result was
        decided or later (the latest one taken can be a simulated second older: still moving)."""
        return self.positions(self.joints.after(waits.result_time(client)))

    def test_0_joint_states_carry_all_seven_joints_at_50_hz(self):
        """As katana_arm_gazebo's: joint_state_controller alone, fingers included (their effort
        transmissions), at its publish_rate; the gripper plugin publishes none."""
        t0 = self.joints.fresh().header.stamp.to_sec()
        end = self.joints.after(t0 + 1.0).header.stamp.to_sec()     # in order: the second's are in
        history = self.joints.history
        self.assertEqual({tuple(m.name) for m in history},
                         {tuple(JOINTS) + ("katana_r_finger_joint", "katana_l_finger_joint")})
        stamps = [m.header.stamp.to_sec() for m in history if t0 <= m.header.stamp.to_sec() <= end]
        # at real_time_factor 0 messages can be lost on the way (a publisher's queue overflows, a
        # burst of 20 under load): every gap must be a whole number of periods, most of them one
        gaps = [(b - a) / PERIOD for a, b in zip(stamps, stamps[1:])]
        periods = [max(1, round(g)) for g in gaps]
        self.assertTrue(gaps and all(abs(g - k) < 0.05 for g, k in zip(gaps, periods)),
                        "/joint_states not on a 50 Hz grid of simulated time: gaps %s periods" % gaps)
        self.assertGreater(periods.count(1), len(periods) / 2,
                           "/joint_states mostly slower than 50 Hz: gaps %s periods" % gaps)

    def test_1_trajectory_reaches_five_joint_target(self):
        target = [1.5, 1.1, -1.4, 0.7, 0.5]   # to the left, clear of the cans
        goal = FollowJointTrajectoryGoal()
        goal.trajectory.joint_names = list(JOINTS)
        goal.trajectory.points = [
            JointTrajectoryPoint(positions=[0.8, 1.5, -1.7, -0.3, 0.2], time_from_start=rospy.Duration(2.0)),
            JointTrajectoryPoint(positions=target, velocities=[0.0] * 5, time_from_start=rospy.Duration(4.0))]
        self.arm.send_goal(goal)
        self.assertTrue(waits.wait_for_result(self.arm, 60), "no result from the trajectory action")
        res = self.arm.get_result()
        self.assertEqual(self.arm.get_state(), GoalStatus.SUCCEEDED, res.error_string)
        positions = self.positions_after(self.arm)
        for name, want in zip(JOINTS, target):
            self.assertLess(abs(positions[name] - want), TOLERANCE,
                            "%s at %.4f, goal %.4f" % (name, positions[name], want))

    def _grip(self, position, max_effort=0.0):
        goal = GripperCommandGoal()
        goal.command.position, goal.command.max_effort = position, max_effort
        self.gripper.send_goal(goal)
        self.assertTrue(waits.wait_for_result(self.gripper, 30), "no result from the gripper")
        return self.gripper.get_state(), self.gripper.get_result(), self.gripper.get_goal_status_text()

    def test_2_gripper_opens_and_closes_on_nothing(self):
        state, res, text = self._grip(0.3)
        self.assertEqual(state, GoalStatus.SUCCEEDED, text)
        self.assertTrue(res.reached_goal, text)
        self.assertAlmostEqual(self.positions_after(self.gripper)["katana_l_finger_joint"], 0.3, delta=0.02)
        state, res, text = self._grip(-0.44, 0.3)
        self.assertEqual(state, GoalStatus.SUCCEEDED, text)
        self.assertTrue(res.reached_goal, text)
        self.assertFalse(res.stalled, text)
        self.assertNotIn("holding", text)
        self.joints.wait(lambda m: abs(self.positions(m)["katana_r_finger_joint"] + 0.44) < 0.02, 10,
                         "the finger state at -0.44")

    def test_4_kdl_fk_matches_the_simulators_link_poses(self):
        states = rospy.wait_for_message("/gazebo/link_states", LinkStates, timeout=30)
        positions = self.positions(self.joints.fresh())     # the arm stands still since test_2
        q = [positions[j] for j in JOINTS]
        fk = rospy.ServiceProxy("/katana_arm_kinematics/get_fk", GetFK)
        fk.wait_for_service(30)
        res = fk(joint_names=list(JOINTS), positions=q, solver="kdl")
        self.assertTrue(res.success, res.message)
        # the tool frame sits LINK5 along the wrist roll link's x axis; compare the link itself too
        sim = states.pose[states.name.index("katana::katana_motor5_wrist_roll_link")]
        m = kin.link_frames(q)[4]
        base = np.array([0.0, 0.0, 0.75])
        sim_p = np.array([sim.position.x, sim.position.y, sim.position.z]) - base
        self.assertLess(np.linalg.norm(sim_p - m[:3, 3]), 0.002,
                        "wrist roll link: sim %s, FK %s" % (sim_p, m[:3, 3]))
        tool = np.array([res.pose.pose.position.x, res.pose.pose.position.y, res.pose.pose.position.z])
        self.assertLess(np.linalg.norm(tool - kin.tool_position(q)), 1e-6)

    def test_5_ik_service_solves_and_refuses_with_the_reason(self):
        ik = rospy.ServiceProxy("/katana_arm_kinematics/get_ik", GetIK)
        ik.wait_for_service(30)
        target = PoseStamped()
        target.pose.position.x, target.pose.position.y, target.pose.position.z = 0.3, -0.1, 0.2
        for solver in ("kdl", "triangle", "grasp"):
            res = ik(target=target, solver=solver, position_only=True)
            self.assertTrue(res.success, "%s: %s" % (solver, res.message))
            self.assertLess(np.linalg.norm(kin.tool_position(res.positions) - [0.3, -0.1, 0.2]), 1e-3, solver)
        # the same point given in the world frame (the base stands at z 0.75): through tf
        world_target = PoseStamped()
        world_target.header.frame_id = "world"
        p = world_target.pose.position
        p.x, p.y, p.z = 0.3, -0.1, 0.95
        res = ik(target=world_target, solver="kdl", position_only=True)
        self.assertTrue(res.success, res.message)
        self.assertLess(np.linalg.norm(kin.tool_position(res.positions) - [0.3, -0.1, 0.2]), 1e-3)
        target.pose.position.x = 1.2
        res = ik(target=target, solver="kdl", position_only=True)
        self.assertFalse(res.success)
        self.assertIn("refused", res.message)
        self.assertIn("reaches at most", res.message)

    def test_6_laser_finds_cans_at_known_poses_within_1cm(self):
        set_state = rospy.ServiceProxy("/gazebo/set_model_state", SetModelState)
        set_state.wait_for_service(30)
        # world poses (the arm stands at (0, 0, 0.75); the laser 0.085 m ahead of its axis)
        poses = {"coke_can_1": (0.43, 0.05), "coke_can_2": (0.30, -0.18)}
        for name, (x, y) in poses.items():
            st = ModelState(model_name=name, reference_frame="world")
            st.pose.position.x, st.pose.position.y, st.pose.position.z = x, y, 0.811
            st.pose.orientation.w = 1.0
            self.assertTrue(set_state(st).success)
        # the simulator's time now (this node's clock can be a simulated second behind): a
        # detection stamped 0.3 s later comes from a scan of the moved cans
        t0 = rospy.ServiceProxy("/gazebo/get_world_properties", GetWorldProperties)().sim_time
        waits.wait_until(lambda: self.detections is not None
                         and self.detections.header.stamp.to_sec() > t0 + 0.3
                         and len(self.detections.poses) == 2, 30, "two detections after the cans moved")
        self.assertEqual(self.detections.header.frame_id, "katana_laser_link")
        found = [(p.position.x + 0.085, p.position.y) for p in self.detections.poses]
        for name, (x, y) in poses.items():
            err = min(math.hypot(fx - x, fy - y) for fx, fy in found)
            self.assertLess(err, 0.01, "%s at (%.3f, %.3f): nearest detection %.4f m away (%s)"
                            % (name, x, y, err, found))

    def test_7_keyboard_teleop_moves_a_joint_and_restores_the_terminal(self):
        master, slave = os.openpty()
        before = termios.tcgetattr(slave)
        proc = subprocess.Popen(["rosrun", "katana_sim", "keyboard_teleop", "_increment:=0.2"],
                                stdin=slave, stdout=slave, stderr=subprocess.STDOUT)
        try:
            # a process start-up: wall-clock time (simulated time runs faster than real time here)
            deadline = time.monotonic() + 180
            while termios.tcgetattr(slave) == before and time.monotonic() < deadline and proc.poll() is None:
                time.sleep(0.1)
            self.assertNotEqual(termios.tcgetattr(slave), before,
                                "the teleop never put the terminal in cbreak mode")
            start = self.positions(self.joints.fresh())["katana_motor1_pan_joint"]
            os.write(master, b"0w")
            self.joints.wait(lambda m: abs(self.positions(m)["katana_motor1_pan_joint"] - start - 0.2) < 0.03,
                             30, "joint 0 to move by the 0.2 rad increment")
            os.write(master, b"q")
            self.assertEqual(proc.wait(timeout=30), 0)
        finally:
            if proc.poll() is None:
                proc.kill()
        self.assertEqual(termios.tcgetattr(slave), before, "the terminal was not restored")
        os.close(master)
        os.close(slave)

    def test_3_nan_gripper_goal_is_refused(self):
        state, res, text = self._grip(float("nan"))
        self.assertEqual(state, GoalStatus.ABORTED)
        self.assertIn("not a finite number", text)
        self.assertTrue(math.isfinite(self.positions_after(self.gripper)["katana_r_finger_joint"]))


if __name__ == "__main__":
    rostest.rosrun("katana_sim", "katana_arm_check", KatanaArm)
