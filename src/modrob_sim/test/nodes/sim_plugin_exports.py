#!/usr/bin/env python3
"""rostest node: a plugin exported by a package in another workspace folder is found by its file
name. It runs the user's command, ``roslaunch exported_probe probe_world.launch`` (a launch file
that names only modrob_sim and its own package; nobody sets ~plugin_modules), with that folder
added to ROS_PACKAGE_PATH, and waits for the plugin's report: loaded from the package's export,
its <label> read, and stepping."""
import os
import signal
import subprocess
import sys
import tempfile
import unittest

import rospy
import rostest
from std_msgs.msg import String

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sim_helpers import Latest, wait_for  # noqa: E402

TEST_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OTHER_WS = os.path.join(TEST_DIR, "fixtures", "other_ws", "src")


class SimPluginExports(unittest.TestCase):
    def setUp(self):
        env = dict(os.environ)
        env["ROS_PACKAGE_PATH"] = OTHER_WS + os.pathsep + env.get("ROS_PACKAGE_PATH", "")
        self.log = tempfile.TemporaryFile(mode="w+")
        self.launch = subprocess.Popen(["roslaunch", "exported_probe", "probe_world.launch"], env=env,
                                       stdout=self.log, stderr=subprocess.STDOUT, text=True,
                                       start_new_session=True)

    def tearDown(self):
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
        report = Latest("/exported_probe/probe_robot", String)
        ok = wait_for(lambda: report.get() is not None and report.get().data.startswith("running")
                      and int(report.get().data.rsplit("=", 1)[1]) > 100, 90.0)
        msg = report.get().data if report.get() else "nothing on /exported_probe/probe_robot"
        self.assertTrue(ok, "%s; roslaunch said:\n%s" % (msg, self.launch_output()))
        self.assertIn("label=from_another_workspace", msg)


if __name__ == "__main__":
    rospy.init_node("sim_plugin_exports_test")
    rostest.rosrun("modrob_sim", "sim_plugin_exports", SimPluginExports)
