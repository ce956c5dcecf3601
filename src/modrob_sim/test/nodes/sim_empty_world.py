#!/usr/bin/env python3
"""rostest node: empty_world.launch (gui:=false) comes up headless as gazebo_ros's does:
/use_sim_time set, /clock running (or held when paused:=true), the world file's ground plane
spawned and shown on /gazebo/world_markers, the services answering, no GUI process."""
import sys
import time
import unittest

import rosnode
import rospy
import rostest
from gazebo_msgs.msg import PerformanceMetrics
from rosgraph_msgs.msg import Clock
from visualization_msgs.msg import MarkerArray

from modrob_sim.waits import wait_until

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from sim_helpers import Gazebo, Latest  # noqa: E402


class SimEmptyWorld(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.expect_paused = rospy.get_param("~expect_paused", False)
        cls.expect_time_step = rospy.get_param("~expect_time_step", 0.001)
        cls.gz = Gazebo()

    def test_use_sim_time(self):
        self.assertIs(rospy.get_param("/use_sim_time"), True)

    def test_clock(self):
        clock = Latest("/clock", Clock)
        self.assertTrue(wait_until(lambda: clock.get() is not None, 20.0), "no /clock")
        first = clock.get().clock
        if self.expect_paused:
            # nothing to wait for: a wall second in which a running simulator would have published
            # hundreds of newer clock messages
            time.sleep(1.0)
            self.assertEqual(clock.get().clock, first)
            self.assertTrue(self.gz.get_physics_properties().pause)
        else:
            self.assertTrue(wait_until(lambda: clock.get().clock > first, 10.0), "/clock does not advance")

    def test_world_file_loaded_and_shown(self):
        self.assertIn("ground_plane", self.gz.get_world_properties().model_names)
        markers = Latest("/gazebo/world_markers", MarkerArray)
        self.assertTrue(wait_until(lambda: markers.get() is not None, 10.0), "no world markers (latched)")
        ground = [m for m in markers.get().markers if m.ns == "ground_plane"]
        self.assertTrue(ground)
        self.assertGreater(ground[0].scale.x, 10.0)

    def test_physics_from_launch_arguments(self):
        p = self.gz.get_physics_properties()
        self.assertAlmostEqual(p.time_step, self.expect_time_step)
        self.assertAlmostEqual(p.gravity.z, -9.81)
        self.assertEqual(p.max_update_rate, 0.0)      # real_time_factor:=0

    def test_headless(self):
        nodes = rosnode.get_node_names()
        self.assertIn("/gazebo", nodes)
        self.assertNotIn("/gazebo_gui", nodes)

    def test_performance_metrics(self):
        if self.expect_paused:
            return
        perf = Latest("/gazebo/performance_metrics", PerformanceMetrics)
        self.assertTrue(wait_until(lambda: perf.get() is not None, 10.0))
        self.assertGreater(perf.get().real_time_factor, 0.0)


if __name__ == "__main__":
    rospy.init_node("sim_empty_world_test")
    rostest.rosrun("modrob_sim", "sim_empty_world", SimEmptyWorld)
