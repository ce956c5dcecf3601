#!/usr/bin/env python3
"""What a franka_gazebo user sees, on the Panda-style test arm: ``initialized`` comes, the
controllers run, FollowJointTrajectory reaches its goal, joint states and tf are complete, and the
gripper grasps a cube and the arm lifts it."""
import unittest

import actionlib
import rospy
import rostest
import tf2_ros
from control_msgs.msg import FollowJointTrajectoryAction, FollowJointTrajectoryGoal, GripperCommandAction
from control_msgs.msg import GripperCommandGoal
from controller_manager_msgs.srv import ListControllers
from franka_gripper.msg import GraspAction, GraspGoal, HomingAction, HomingGoal, MoveAction, MoveGoal
from franka_msgs.msg import FrankaState
from gazebo_msgs.srv import GetModelState, SpawnModel
from geometry_msgs.msg import Pose
from sensor_msgs.msg import JointState
from std_msgs.msg import Bool
from trajectory_msgs.msg import JointTrajectoryPoint

from modrob_sim import waits

ARM = ["panda_joint%d" % i for i in range(1, 8)]
CUBE = """<sdf version="1.6"><model name="cube"><link name="l">
<inertial><mass>0.05</mass><inertia><ixx>4e-5</ixx><iyy>4e-5</iyy><izz>8e-6</izz><ixy>0</ixy><ixz>0</ixz>
<iyz>0</iyz></inertia></inertial>
<collision name="c"><geometry><box><size>0.03 0.03 %g</size></box></geometry>
<surface><friction><ode><mu>1</mu><mu2>1</mu2></ode></friction></surface></collision></link></model></sdf>"""


# Every wait below is in wall seconds (modrob_sim.waits): the simulator runs at real_time_factor 0,
# where a simulated-time timeout (actionlib's, tf2's, rospy's) is gone in a fraction of a wall second,
# before the spawners or the listener are ready on a loaded machine.


def wait_true(topic, timeout):
    latest = waits.Latest(topic, Bool)
    return waits.wait_until(lambda: latest.msg is not None and latest.msg.data, timeout)


def server(action, cls, timeout=30.0):
    client = actionlib.SimpleActionClient(action, cls)
    missing = waits.wait_for_action_servers(((client, action),), timeout)
    assert missing is None, "no %s action server within %.0f s" % (missing, timeout)
    return client


class MiniPanda(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tf = tf2_ros.Buffer()
        cls.listener = tf2_ros.TransformListener(cls.tf)

    def controllers_running(self, names, timeout=60.0):
        rospy.wait_for_service("/controller_manager/list_controllers", timeout)
        lc = rospy.ServiceProxy("/controller_manager/list_controllers", ListControllers)
        states = {}

        def running():
            states.update({c.name: c.state for c in lc().controller})
            return all(states.get(n) == "running" for n in names)
        waits.wait_until(running, timeout)
        return states

    def tcp(self):
        return waits.lookup_transform(self.tf, "world", "panda_hand_tcp", 20).transform.translation

    def test_1_initialized_and_controllers(self):
        self.assertTrue(wait_true("/initialized", 60), "initialized never became true")
        states = self.controllers_running(["franka_state_controller", "franka_gripper",
                                           "effort_joint_trajectory_controller"])
        self.assertEqual(states.get("effort_joint_trajectory_controller"), "running", states)

    def test_2_joint_states_and_tf(self):
        js = rospy.wait_for_message("/joint_states", JointState, timeout=30)
        self.assertEqual(sorted(js.name), sorted(ARM + ["panda_finger_joint1", "panda_finger_joint2"]))
        state = rospy.wait_for_message("/franka_state_controller/franka_states", FrankaState, timeout=30)
        self.assertEqual(len(state.q), 7)
        for frame in ["panda_link%d" % i for i in range(9)] + ["panda_hand", "panda_leftfinger",
                                                               "panda_rightfinger", "panda_hand_tcp",
                                                               "panda_NE", "panda_EE", "panda_K"]:
            known = waits.wait_until(lambda: self.tf.can_transform("world", frame, rospy.Time(0)), 20)
            self.assertTrue(known, "no tf world -> %s within 20 s" % frame)

    def test_3_trajectory_grasp_and_lift(self):
        self.controllers_running(["effort_joint_trajectory_controller", "franka_gripper"])
        # 1. FollowJointTrajectory to a goal (within the controller's 0.05 rad goal tolerance)
        jtc = server("/effort_joint_trajectory_controller/follow_joint_trajectory",
                     FollowJointTrajectoryAction)
        start = rospy.wait_for_message("/franka_state_controller/joint_states", JointState, timeout=30)
        target = list(start.position)
        target[0] += 0.3        # swing to the side and back: a real motion of every joint's loop
        self.move(jtc, target)
        target[0] -= 0.3
        self.move(jtc, target)
        # 2. open, spawn a cube between the fingers, grasp it
        homing = server("/franka_gripper/homing", HomingAction)
        self.run_goal(homing, HomingGoal())
        self.assertTrue(homing.get_result().success)
        width = sum(rospy.wait_for_message("/franka_gripper/joint_states", JointState, timeout=10).position)
        self.assertAlmostEqual(width, 0.08, delta=0.002)
        tcp = self.tcp()
        self.assertLess(tcp.z, 0.3, "the test pose should put the fingers near the ground")
        height = tcp.z + 0.03     # a cube on the ground that reaches 3 cm above the finger tips' centre
        spawn = rospy.ServiceProxy("/gazebo/spawn_sdf_model", SpawnModel)
        pose = Pose()
        pose.position.x, pose.position.y, pose.position.z = tcp.x, tcp.y, height / 2.0
        pose.orientation.w = 1.0
        self.assertTrue(spawn("cube", CUBE % height, "", pose, "world").success)
        grasp = server("/franka_gripper/grasp", GraspAction)
        goal = GraspGoal(width=0.03, speed=0.05, force=10.0)
        goal.epsilon.inner = goal.epsilon.outer = 0.005
        self.run_goal(grasp, goal)
        result = grasp.get_result()
        self.assertTrue(result.success, result.error)
        # 3. lift: the cube comes along
        get = rospy.ServiceProxy("/gazebo/get_model_state", GetModelState)
        z0 = get("cube", "world").pose.position.z
        lifted = list(target)
        lifted[1] -= 0.25
        lifted[3] += 0.25
        self.move(jtc, lifted)
        self.assertGreater(get("cube", "world").pose.position.z - z0, 0.05)
        # 4. a move that the cube blocks fails, as franka_gazebo's; opening releases it
        move = server("/franka_gripper/move", MoveAction)
        self.run_goal(move, MoveGoal(width=0.0, speed=0.05))
        self.assertFalse(move.get_result().success)
        gc = server("/franka_gripper/gripper_action", GripperCommandAction)
        g = GripperCommandGoal()
        g.command.position = 0.035
        self.run_goal(gc, g)
        self.assertTrue(gc.get_result().reached_goal)

    def run_goal(self, client, goal, timeout=60.0):
        """send_goal_and_wait with a wall-time limit (actionlib's is simulated time: checked before
        the goal's state, it runs out while this node waits for the CPU at real_time_factor 0)."""
        client.send_goal(goal)
        self.assertTrue(waits.wait_for_result(client, timeout),
                        "no result from %s within %.0f s" % (client.action_client.ns, timeout))

    def move(self, jtc, target):
        goal = FollowJointTrajectoryGoal()
        goal.trajectory.joint_names = ARM
        goal.trajectory.points = [JointTrajectoryPoint(positions=target, time_from_start=rospy.Duration(1.5))]
        self.run_goal(jtc, goal)
        self.assertEqual(jtc.get_result().error_code, 0, jtc.get_result().error_string)
        js = rospy.wait_for_message("/franka_state_controller/joint_states", JointState, timeout=10)
        err = max(abs(a - b) for a, b in zip(js.position, target))
        self.assertLess(err, 0.05, "joint error %.4f rad after the goal" % err)


if __name__ == "__main__":
    rospy.init_node("mini_panda_check", anonymous=True)
    rostest.rosrun("franka_sim", "mini_panda", MiniPanda)
