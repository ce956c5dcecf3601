#!/usr/bin/env python3
"""rostest node for control_manager.test."""
import os
import sys
import unittest

import rospy
import rostest
from controller_manager_msgs.srv import (ListControllers, ListControllerTypes, LoadController,
                                         ReloadControllerLibraries, SwitchController, UnloadController)
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64

from modrob_sim import waits
from modrob_sim.waits import sim_sleep, wait_until

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from control_common import Latest, RosoutCollector  # noqa: E402

STRICT, BEST_EFFORT = 2, 1


class Manager(object):
    def __init__(self, ns):
        base = ns + "/controller_manager/"
        for name, cls in (("list_controllers", ListControllers), ("list_controller_types",
                                                                  ListControllerTypes),
                          ("load_controller", LoadController), ("unload_controller", UnloadController),
                          ("switch_controller", SwitchController),
                          ("reload_controller_libraries", ReloadControllerLibraries)):
            rospy.wait_for_service(base + name, timeout=60)
            setattr(self, name, rospy.ServiceProxy(base + name, cls))

    def states(self):
        return {c.name: c.state for c in self.list_controllers().controller}

    def switch(self, start, stop, strictness=STRICT):
        return self.switch_controller(start, stop, strictness, False, 0.0).ok


class ControllerManagerRoundTrip(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("control_manager_check")
        cls.log = RosoutCollector()
        cls.wheels = Manager("/wheels")
        cls.arm = Manager("/arm1p")
        cls.joints = Latest("/wheels/joint_states", JointState)
        assert cls.wheels.load_controller("joint_state_controller").ok
        assert cls.wheels.switch(["joint_state_controller"], [])
        wait_until(lambda: cls.joints.msg is not None, 30, "/wheels/joint_states")

    def velocity(self, joint):
        msg = self.joints.fresh()       # a state from now, not one still on its way
        return msg.velocity[msg.name.index(joint)]

    def assert_holds_velocity(self, joint, want, delta=0.04):
        """``joint`` comes to ``want`` and is still there 1 s of simulated time later. Waited for
        in wall time: at real_time_factor 0 the command's delivery to the simulator (wall time)
        can take seconds of simulated time on a loaded machine."""
        wait_until(lambda: abs(self.velocity(joint) - want) < delta, 30, "%s at %g rad/s" % (joint, want))
        sim_sleep(1.0)
        self.assertAlmostEqual(self.velocity(joint), want, delta=delta)

    def test_1_types(self):
        types = self.wheels.list_controller_types()
        for t in ("joint_state_controller/JointStateController",
                  "effort_controllers/JointPositionController", "effort_controllers/JointVelocityController",
                  "effort_controllers/JointEffortController", "position_controllers/JointPositionController",
                  "velocity_controllers/JointVelocityController",
                  "position_controllers/JointTrajectoryController",
                  "effort_controllers/JointTrajectoryController"):
            self.assertIn(t, types.types)
        self.assertEqual(len(types.base_classes), len(types.types))

    def test_2_round_trip_and_velocity_interface_wheel(self):
        m = self.wheels
        self.assertTrue(m.load_controller("wheel_v_controller").ok)
        self.assertEqual(m.states()["wheel_v_controller"], "initialized")
        self.assertFalse(m.load_controller("wheel_v_controller").ok)          # already loaded
        self.assertTrue(m.switch(["wheel_v_controller"], []))
        listed = {c.name: c for c in m.list_controllers().controller}["wheel_v_controller"]
        self.assertEqual(listed.state, "running")
        self.assertEqual(listed.type, "velocity_controllers/JointVelocityController")
        self.assertEqual(listed.claimed_resources[0].hardware_interface,
                         "hardware_interface::VelocityJointInterface")
        self.assertEqual(listed.claimed_resources[0].resources, ["wheel_v"])
        pub = waits.command_publisher("/wheels/wheel_v_controller/command", Float64, 20)
        pub.publish(Float64(2.0))
        self.assert_holds_velocity("wheel_v", 2.0)
        self.assertFalse(m.unload_controller("wheel_v_controller").ok)          # still running
        self.assertTrue(m.switch([], ["wheel_v_controller"]))
        self.assertEqual(m.states()["wheel_v_controller"], "stopped")
        self.assertTrue(m.unload_controller("wheel_v_controller").ok)
        self.assertNotIn("wheel_v_controller", m.states())
        pub.unregister()

    def test_3_effort_velocity_controller_and_resource_conflict(self):
        m = self.wheels
        self.assertTrue(m.load_controller("wheel_e_controller").ok)
        self.assertTrue(m.load_controller("wheel_e_effort_controller").ok)
        self.assertTrue(m.switch(["wheel_e_controller"], []))
        self.assertFalse(m.switch(["wheel_e_effort_controller"], [], BEST_EFFORT))       # same joint
        self.log.wait_for("Resource conflict", "wheel_e")
        pub = waits.command_publisher("/wheels/wheel_e_controller/command", Float64, 20)
        pub.publish(Float64(2.0))
        self.assert_holds_velocity("wheel_e", 2.0)
        self.assertTrue(m.switch(["wheel_e_effort_controller"], ["wheel_e_controller"]))  # swap in one switch
        self.assertEqual(m.states()["wheel_e_effort_controller"], "running")
        self.assertTrue(m.switch([], ["wheel_e_effort_controller"]))
        pub.unregister()

    def test_4_bad_configurations_are_refused_with_clear_messages(self):
        m = self.wheels
        self.assertFalse(m.load_controller("typo_controller").ok)
        text = self.log.wait_for("effort_controllers/JointVelocityControler", "does not exist")
        self.assertIn("velocity_controllers/JointVelocityController", text)            # known types listed
        self.assertFalse(m.load_controller("no_joint_controller").ok)
        self.log.wait_for("/wheels/no_joint_controller/joint")
        self.assertFalse(m.load_controller("no_pid_controller").ok)
        self.log.wait_for("/wheels/no_pid_controller/pid")
        self.assertFalse(m.load_controller("wheel_v_effort_controller").ok)
        self.log.wait_for("wheel_v", "VelocityJointInterface")
        self.assertFalse(m.load_controller("not_on_the_parameter_server").ok)
        self.log.wait_for("type was not specified", "/wheels/not_on_the_parameter_server")
        self.assertFalse(m.switch(["ghost"], [], STRICT))
        self.assertTrue(m.switch(["ghost"], [], BEST_EFFORT))
        self.assertFalse(m.reload_controller_libraries(False).ok)                       # controllers loaded

    def test_5_position_interface_with_pid_gains(self):
        m = self.arm
        self.assertTrue(m.load_controller("shoulder_controller").ok)
        self.assertTrue(m.switch(["shoulder_controller"], []))
        # no joint_state_controller here: one loaded through the manager reads the joint
        self.assertFalse(m.load_controller("jsc").ok)                   # not on the parameter server yet
        rospy.set_param("/arm1p/jsc", {"type": "joint_state_controller/JointStateController",
                                       "publish_rate": 50})
        self.assertTrue(m.load_controller("jsc").ok)
        self.assertTrue(m.switch(["jsc"], []))
        joints = Latest("/arm1p/joint_states", JointState)

        def shoulder(msg):
            return msg.position[msg.name.index("shoulder")]
        q0 = shoulder(joints.wait(timeout=30, what="the shoulder's state"))
        pub = waits.command_publisher("/arm1p/shoulder_controller/command", Float64, 20)
        pub.publish(Float64(0.5))
        # the simulated time counts from the command's arrival (the joint's first move), not from its
        # publication: at real_time_factor 0 its delivery can take seconds of simulated time
        joints.wait(lambda msg: abs(shoulder(msg) - q0) > 1e-3, 30, "the shoulder moving to 0.5")
        moved = next(msg for msg in joints.history if abs(shoulder(msg) - q0) > 1e-3)
        q = shoulder(joints.after(moved.header.stamp.to_sec() + 4.0))
        self.assertLess(abs(q - 0.5), 0.01, "shoulder at %.4f 4 s after it left %.4f" % (q, q0))
        pub.unregister()


if __name__ == "__main__":
    rostest.rosrun("modrob_sim", "control_manager", ControllerManagerRoundTrip)
