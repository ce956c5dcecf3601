#!/usr/bin/env python3
"""rostest node for robots built and spawned by urdf_and_gazebo.launch in the modrob simulator:

1. every controller of every robot (from /modrob_robots) is running;
2. commanded joint angles are reached on each robot (|error| < ~tolerance, joints at rest);
3. with physics paused, KDL forward kinematics of each robot's robot_description at the simulator's
   joint positions agrees with the simulator's link poses (gazebo_msgs services) within 1 mm.

~robots: expected number of robots; ~targets: {joint name: angle} commanded on every robot;
~tolerance: rad; ~out_dir (optional): removed at the end.
"""
import math
import shutil
import unittest
import xml.etree.ElementTree as ET

import rospy
import rostest
from controller_manager_msgs.srv import ListControllers
from gazebo_msgs.srv import GetJointProperties, GetLinkState
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64
from std_srvs.srv import Empty

from modrob_kinematics.kdl_urdf import KinematicChain, tree_from_urdf_string
from modrob_sim.waits import wait_until

FK_TOLERANCE = 0.001


class SimRobotsCheck(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.n = rospy.get_param("~robots")
        cls.targets = rospy.get_param("~targets")
        cls.tolerance = rospy.get_param("~tolerance", 0.02)
        cls.robots = wait_until(lambda: rospy.get_param("/modrob_robots", None), 60, "/modrob_robots")
        cls.states = {}
        cls.subs = [rospy.Subscriber("%s/joint_states" % r["namespace"], JointState, cls._on_state,
                                     callback_args=r["name"], queue_size=1) for r in cls.robots]
        cls.pubs = {}

    @classmethod
    def _on_state(cls, msg, name):
        cls.states[name] = msg

    def step_1_controllers_running(self):
        self.assertEqual(len(self.robots), self.n)
        for r in self.robots:
            srv_name = "%s/controller_manager/list_controllers" % r["namespace"]
            rospy.wait_for_service(srv_name, timeout=60)
            proxy = rospy.ServiceProxy(srv_name, ListControllers)

            def all_running():
                states = {c.name: c.state for c in proxy().controller}
                return all(states.get(c) == "running" for c in r["controllers"]) and states
            states = wait_until(all_running, 60, "%s: controllers %s running" % (r["name"], r["controllers"]))
            self.assertEqual(set(states), set(r["controllers"]))

    def step_2_targets_reached(self):
        for r in self.robots:
            for joint, value in self.targets.items():
                topic = "%s/%s_position_controller/command" % (r["namespace"], joint)
                pub = rospy.Publisher(topic, Float64, queue_size=1, latch=True)
                self.pubs[topic] = pub
                pub.publish(Float64(value))

        def reached(r):
            msg = self.states.get(r["name"])
            if msg is None:
                return False
            pos = dict(zip(msg.name, msg.position))
            vel = dict(zip(msg.name, msg.velocity))
            ok = all(abs(pos[j] - v) < self.tolerance for j, v in self.targets.items())
            return ok and all(abs(vel[j]) < 1e-3 for j in r["joints"])
        for r in self.robots:
            wait_until(lambda: reached(r), 60, "%s: joints at %s and at rest" % (r["name"], self.targets))

    def step_3_fk_matches_link_states(self):
        """Pause physics and compare, at that one instant, KDL FK of the simulator's joint
        positions with its link poses. (Pairing the latest /joint_states, 50 Hz, with a later
        /gazebo/link_states let a PID-held arm's sub-millimetre limit cycle into the comparison.)"""
        rospy.wait_for_service("/gazebo/pause_physics", timeout=30)
        pause = rospy.ServiceProxy("/gazebo/pause_physics", Empty)
        unpause = rospy.ServiceProxy("/gazebo/unpause_physics", Empty)
        joint_props = rospy.ServiceProxy("/gazebo/get_joint_properties", GetJointProperties)
        link_state = rospy.ServiceProxy("/gazebo/get_link_state", GetLinkState)
        pause()
        try:
            for r in self.robots:
                self._compare_paused(r, joint_props, link_state)
        finally:
            unpause()

    def _compare_paused(self, r, joint_props, link_state):
        urdf = rospy.get_param("%s/robot_description" % r["namespace"])
        tree = tree_from_urdf_string(urdf)
        q = {}
        for je in ET.fromstring(urdf).findall("joint"):
            if je.get("type") in ("fixed", "floating", "planar"):
                continue
            props = joint_props("%s::%s" % (r["name"], je.get("name")))
            self.assertTrue(props.success, props.status_message)
            q[je.get("name")] = props.position[0]
        checked = 0
        for link in tree.link_names:
            if link == "world":
                continue
            state = link_state("%s::%s" % (r["name"], link), "world")
            if not state.success:
                continue
            chain = KinematicChain(tree, "world", link)
            frame = chain.fk([q[j] for j in chain.joint_names])
            pose = state.link_state.pose
            p = pose.position
            err = math.sqrt((frame.p[0] - p.x) ** 2 + (frame.p[1] - p.y) ** 2 + (frame.p[2] - p.z) ** 2)
            key = "%s::%s" % (r["name"], link)
            self.assertLess(err, FK_TOLERANCE, "%s: KDL %s vs the simulator (%.4f %.4f %.4f)"
                            % (key, list(frame.p), p.x, p.y, p.z))
            x, y, z, w = frame.M.GetQuaternion()
            o = pose.orientation
            self.assertGreater(abs(x * o.x + y * o.y + z * o.z + w * o.w), 1 - 1e-5, key)
            checked += 1
        self.assertGreaterEqual(checked, len(r["joints"]), "%s: too few links in the simulator" % r["name"])

    def test_sim_robots(self):
        self.step_1_controllers_running()
        self.step_2_targets_reached()
        self.step_3_fk_matches_link_states()
        out_dir = rospy.get_param("~out_dir", "")
        if out_dir:
            shutil.rmtree(out_dir, ignore_errors=True)


if __name__ == "__main__":
    rospy.init_node("sim_robots_check")
    rostest.rosrun("modrob_build", "sim_robots_check", SimRobotsCheck)
