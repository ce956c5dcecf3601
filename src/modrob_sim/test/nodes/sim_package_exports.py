#!/usr/bin/env python3
"""rostest node: what a package in another workspace folder exports is found as Gazebo finds it.
It runs the user's command, ``roslaunch exported_probe probe_world.launch`` (a launch file that
names only modrob_sim and its own package; nobody sets ~plugin_modules or GAZEBO_MODEL_PATH), with
that folder added to ROS_PACKAGE_PATH:
- the plugin it exports (libexported_probe.so) loads by its file name, reads its <label>, steps;
- ``world_name:=worlds/probe_yard.world`` is found through its gazebo_media_path export, the
  world's model://probe_crate through its gazebo_model_path export, and the world's model that
  only Gazebo's online database has is skipped: the node starts and the crate is there."""
import os
import signal
import subprocess
import sys
import tempfile
import unittest

import rospy
import rostest
from gazebo_msgs.srv import GetModelState, GetWorldProperties
from std_msgs.msg import String

from modrob_sim.waits import wait_until

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sim_helpers import Latest  # noqa: E402

TEST_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OTHER_WS = os.path.join(TEST_DIR, "fixtures", "other_ws", "src")


class SimPackageExports(unittest.TestCase):
    def start(self, *args):
        env = dict(os.environ)
        env["ROS_PACKAGE_PATH"] = OTHER_WS + os.pathsep + env.get("ROS_PACKAGE_PATH", "")
        self.log = tempfile.TemporaryFile(mode="w+")
        self.launch = subprocess.Popen(["roslaunch", "exported_probe", "probe_world.launch"] + list(args),
                                       env=env, stdout=self.log, stderr=subprocess.STDOUT, text=True,
                                       start_new_session=True)

    def tearDown(self):
        if not hasattr(self, "launch"):
            return
        os.killpg(self.launch.pid, signal.SIGINT)
        try:
            self.launch.wait(timeout=30)
        except subprocess.TimeoutExpired:
            os.killpg(self.launch.pid, signal.SIGKILL)
            self.launch.wait()
        self.log.close()

    def launch_output(self):
        self.log.seek(0)
        return self.log.read()[-4000:]

    def test_exported_plugin_is_loaded_by_file_name(self):
        self.start()
        report = Latest("/exported_probe/probe_robot", String)
        ok = wait_until(lambda: report.get() is not None and report.get().data.startswith("running")
                        and int(report.get().data.rsplit("=", 1)[1]) > 100, 90.0)
        msg = report.get().data if report.get() else "nothing on /exported_probe/probe_robot"
        self.assertTrue(ok, "%s; roslaunch said:\n%s" % (msg, self.launch_output()))
        self.assertIn("label=from_another_workspace", msg)

    def test_exported_world_and_model_paths_and_an_offline_model(self):
        self.start("world_name:=worlds/probe_yard.world")
        rospy.wait_for_service("/gazebo/get_world_properties", timeout=90.0)
        props = rospy.ServiceProxy("/gazebo/get_world_properties", GetWorldProperties)
        ok = wait_until(lambda: "probe_robot" in props().model_names, 60.0)
        names = props().model_names
        self.assertTrue(ok, "models %s; roslaunch said:\n%s" % (names, self.launch_output()))
        self.assertEqual(sorted(names), ["ground_plane", "probe_crate", "probe_robot"])
        crate = rospy.ServiceProxy("/gazebo/get_model_state", GetModelState)("probe_crate", "world")
        self.assertTrue(crate.success, crate.status_message)
        self.assertAlmostEqual(crate.pose.position.x, 1.5, places=3)
        self.assertIn("only_in_the_online_database", self.launch_output())


if __name__ == "__main__":
    rospy.init_node("sim_package_exports_test")
    rostest.rosrun("modrob_sim", "sim_package_exports", SimPackageExports)
