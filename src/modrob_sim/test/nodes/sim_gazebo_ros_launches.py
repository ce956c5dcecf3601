#!/usr/bin/env python3
"""rostest node: gazebo_ros's launch files as modrob_sim has them. shapes_world.launch (gui fixed
to true, as gazebo_ros writes it) comes up on a machine without a display: the GUI warns once and
stays away, the simulation runs with the world's three shapes; gzclient itself, started without a
display, says so and exits cleanly."""
import os
import subprocess
import sys
import unittest

import rosnode
import rospy
import rostest
from rosgraph_msgs.msg import Clock

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sim_helpers import Gazebo, Latest, wait_for  # noqa: E402


class SimGazeboRosLaunches(unittest.TestCase):
    def test_shapes_world_runs_headless_with_gui_true(self):
        gz = Gazebo()
        names = gz.get_world_properties().model_names
        self.assertEqual(sorted(names), ["box", "cylinder", "ground_plane", "sphere"])
        clock = Latest("/clock", Clock)
        self.assertTrue(wait_for(lambda: clock.get() is not None, 20.0), "no /clock")
        first = clock.get().clock
        self.assertTrue(wait_for(lambda: clock.get().clock.to_sec() > first.to_sec() + 0.5, 30.0),
                        "the simulation does not run on")
        # the box stands where the world put it, 1 m tall on the ground
        box = gz.get_model_state("box", "world")
        self.assertAlmostEqual(box.pose.position.z, 0.5, places=2)
        # no RViz was started
        self.assertFalse([n for n in rosnode.get_node_names() if "rviz" in n])

    def test_gzclient_without_display_warns_and_exits_cleanly(self):
        env = dict(os.environ, DISPLAY="")
        run = subprocess.run(["rosrun", "modrob_sim", "gzclient", "__name:=gzclient_probe"], env=env,
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=60)
        self.assertEqual(run.returncode, 0, run.stdout)
        self.assertIn("there is no display (DISPLAY is not set)", run.stdout)
        self.assertIn("the simulation runs on", run.stdout)


if __name__ == "__main__":
    rospy.init_node("sim_gazebo_ros_launches_test")
    rostest.rosrun("modrob_sim", "sim_gazebo_ros_launches", SimGazeboRosLaunches)
