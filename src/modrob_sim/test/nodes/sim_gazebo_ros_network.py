#!/usr/bin/env python3
"""rostest node: the node's ROS-level switches as gazebo_ros has them.

mode "off": empty_world.launch enable_ros_network:=false offers /clock and nothing of /gazebo (no
model/link states, no services, no set_parameters), and the simulation still runs.
mode "reconfigure": /gazebo/set_parameters (dynamic_reconfigure) starts with the world's physics,
applies a change through set_physics_properties, a refused value changes nothing, and
max_update_rate keeps within Physics.cfg's bounds."""
import sys
import unittest

import rosgraph
import rospy
import rostest
from dynamic_reconfigure.client import Client
from rosgraph_msgs.msg import Clock

from modrob_sim.waits import wait_until

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from sim_helpers import Gazebo, Latest  # noqa: E402


def graph():
    master = rosgraph.Master("/sim_gazebo_ros_network_test")
    state = master.getSystemState()
    # the node's topics: its own and those its roscpp publishers register (~native_publishing)
    pubs = {t for t, nodes in state[0] if "/gazebo" in nodes or "/gazebo_roscpp" in nodes}
    services = {s for s, nodes in state[2] if "/gazebo" in nodes}
    return pubs, services


class NetworkOff(unittest.TestCase):
    def test_only_clock_and_the_simulation_runs(self):
        clock = Latest("/clock", Clock)
        ok = wait_until(lambda: clock.get() is not None and clock.get().clock.to_sec() > 0.2, 30.0)
        self.assertTrue(ok, "no /clock")
        pubs, services = graph()
        self.assertIn("/clock", pubs)
        gazebo_topics = sorted(t for t in pubs if t.startswith("/gazebo/") and t != "/gazebo/scene_markers")
        self.assertEqual(gazebo_topics, [])
        loggers = ("/get_loggers", "/set_logger_level")
        self.assertEqual(sorted(s for s in services if not s.endswith(loggers)), [])


class Reconfigure(unittest.TestCase):
    def test_set_parameters_reads_and_sets_the_physics(self):
        gz = Gazebo()
        rospy.wait_for_service("/gazebo/set_parameters", timeout=30.0)
        client = Client("/gazebo", timeout=30.0)
        config = client.get_configuration(timeout=30.0)
        self.assertAlmostEqual(config["time_step"], 0.001)
        self.assertAlmostEqual(config["gravity_z"], -9.81)
        self.assertEqual(config["max_update_rate"], 0.0)           # real_time_factor 0: unlimited
        new = client.update_configuration({"time_step": 0.002, "gravity_z": -5.0,
                                           "sor_pgs_iters": 33})
        self.assertAlmostEqual(new["time_step"], 0.002)
        props = gz.get_physics_properties()
        self.assertAlmostEqual(props.time_step, 0.002)
        self.assertAlmostEqual(props.gravity.z, -5.0)
        self.assertEqual(props.ode_config.sor_pgs_iters, 33)
        # a step of 0 s is refused by set_physics_properties: nothing changes, the server says so
        back = client.update_configuration({"time_step": 0.0, "gravity_z": -1.0})
        self.assertAlmostEqual(back["time_step"], 0.002)
        self.assertAlmostEqual(back["gravity_z"], -5.0)
        props = gz.get_physics_properties()
        self.assertAlmostEqual(props.time_step, 0.002)
        self.assertAlmostEqual(props.gravity.z, -5.0)
        # max_update_rate within gazebo_ros's Physics.cfg bounds, [0, 1000]: 1e6 is clamped
        bounds = {d["name"]: (d["min"], d["max"]) for d in client.get_parameter_descriptions()}
        self.assertEqual(bounds["max_update_rate"], (0.0, 1000.0))
        fast = client.update_configuration({"max_update_rate": 1e6})
        self.assertEqual(fast["max_update_rate"], 1000.0)
        self.assertAlmostEqual(gz.get_physics_properties().max_update_rate, 1000.0)
        self.assertEqual(client.update_configuration({"max_update_rate": 0.0})["max_update_rate"], 0.0)
        self.assertEqual(gz.get_physics_properties().max_update_rate, 0.0)


if __name__ == "__main__":
    rospy.init_node("sim_gazebo_ros_network_test")
    mode = rospy.get_param("~mode")
    case = NetworkOff if mode == "off" else Reconfigure
    rostest.rosrun("modrob_sim", "sim_gazebo_ros_network_" + mode, case)
