#!/usr/bin/env python3
"""rostest node for control_spawner.test: runs ``rosrun modrob_sim spawner`` as a user would."""
import signal
import subprocess
import time
import unittest

import rosgraph
import rospy
import rostest

from modrob_sim.waits import controller_states, wait_until

NS = "/arm1"


class Spawner(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("control_spawner_check")
        cls.yaml = rospy.get_param("~yaml")

    def test_1_yaml_controllers_come_up_and_go_away_on_sigint(self):
        proc = subprocess.Popen(["rosrun", "modrob_sim", "spawner", self.yaml, "__ns:=" + NS,
                                 "__name:=spawner_yaml"],
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        try:
            wait_until(lambda: controller_states(NS) == {"joint_state_controller": "running",
                                                         "shoulder_controller": "running"},
                       60, "the YAML's controllers running", period=0.2)
            self.assertEqual(rospy.get_param(NS + "/shoulder_controller/pid/p"), 60.0)
            cmd = ["rosrun", "modrob_sim", "controller_manager", "--namespace", NS, "list"]
            listing = subprocess.run(cmd,
                                     stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=60)
            self.assertEqual(listing.returncode, 0, listing.stdout)
            self.assertIn("shoulder_controller - effort_controllers/JointPositionController ( running )",
                          listing.stdout)
            proc.send_signal(signal.SIGINT)
            out, _ = proc.communicate(timeout=40)
        finally:
            if proc.poll() is None:
                proc.kill()
        self.assertEqual(controller_states(NS), {}, out)
        self.assertIn("Stopping and unloading controllers", out)

    def test_2_missing_manager_times_out_with_a_hint(self):
        out = subprocess.run(["rosrun", "modrob_sim", "spawner", "--timeout", "2", "--namespace", "/nowhere",
                              "some_controller", "__name:=spawner_nowhere"],
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=60)
        self.assertEqual(out.returncode, 1, out.stdout)
        self.assertIn("/nowhere/controller_manager/load_controller", out.stdout)
        self.assertIn("gazebo_ros_control", out.stdout)

    def test_3_quick_exit_once_the_manager_is_gone(self):
        # roslaunch stops the simulator and the spawner at once: the spawner must not wait its
        # --shutdown-timeout (30 s) for services that have gone, which kept roslaunch escalating
        # and left the spawner behind as an orphan
        proc = subprocess.Popen(["rosrun", "modrob_sim", "spawner", self.yaml, "__ns:=" + NS,
                                 "__name:=spawner_gone"],
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        try:
            wait_until(lambda: controller_states(NS).get("shoulder_controller") == "running",
                       60, "the YAML's controllers running", period=0.2)
            rospy.wait_for_service("/gazebo/delete_model", 20)
            from gazebo_msgs.srv import DeleteModel
            self.assertTrue(rospy.ServiceProxy("/gazebo/delete_model", DeleteModel)("arm1").success)
            master = rosgraph.Master(rospy.get_name())

            def gone():
                try:
                    master.lookupService(NS + "/controller_manager/switch_controller")
                    return False
                except rosgraph.MasterException:
                    return True
            wait_until(gone, 20, "arm1's controller_manager services unregistered", period=0.1)
            t0 = time.monotonic()
            proc.send_signal(signal.SIGINT)
            out, _ = proc.communicate(timeout=40)
            took = time.monotonic() - t0
        finally:
            if proc.poll() is None:
                proc.kill()
        self.assertIn("is no longer offered", out)
        self.assertLess(took, 10.0, out)


if __name__ == "__main__":
    rostest.rosrun("modrob_sim", "control_spawner", Spawner)
