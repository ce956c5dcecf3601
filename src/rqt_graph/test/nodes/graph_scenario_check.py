#!/usr/bin/env python3
"""rostest node for graph_bulbs_and_slides.test: once the robot's controller spawner has every
controller running, the graph has /gazebo, the scenario's nodes (motion_publisher,
robot_state_publisher, the spawner), and for every controller the spawner started its topics
with the edges ros_control gives them: motion_publisher -> <c>/command -> /gazebo (live) and
/gazebo -> <c>/state; joint_states from /gazebo to robot_state_publisher. The simulator's topics
are registered by /gazebo_roscpp when it publishes through roscpp (its default, docs/simulator.md)."""
import time
import unittest

import rospy
import rostest
from controller_manager_msgs.srv import ListControllers

from rqt_graph.graph_model import Options, build_graph
from rqt_graph.ros_graph import snapshot


def publisher_of_the_simulator(graph):
    return "/gazebo_roscpp" if "/gazebo_roscpp" in graph.nodes else "/gazebo"


class GraphOfScenario(unittest.TestCase):
    def test_scenario_graph(self):
        rospy.init_node("graph_scenario_check")
        ns = rospy.get_param("~robot_ns")
        rospy.wait_for_service(ns + "/controller_manager/list_controllers", timeout=70)
        listing = rospy.ServiceProxy(ns + "/controller_manager/list_controllers", ListControllers)
        deadline = time.monotonic() + 70
        while True:
            controllers = listing().controller
            if len(controllers) > 1 and all(c.state == "running" for c in controllers):
                break
            self.assertLess(time.monotonic(), deadline, "controllers of %s not all running: %s"
                            % (ns, [(c.name, c.state) for c in controllers]))
            time.sleep(0.5)
        positions = [c.name for c in controllers if c.type.endswith("JointPositionController")]
        self.assertGreaterEqual(len(positions), 6, "the 6-DoF arm's joint controllers")
        cmds = ["%s/%s/command" % (ns, c) for c in positions]
        mp = ns + "/motion_publisher"
        deadline = time.monotonic() + 40
        while True:
            g = build_graph(snapshot(), Options())
            # the connections come up one by one (robot_state_publisher's to joint_states too)
            js = (ns + "/joint_states", ns + "/robot_state_publisher", "")
            if all((mp, c, "") in g.live and (c, "/gazebo", "") in g.live for c in cmds) and js in g.live:
                break
            self.assertLess(time.monotonic(), deadline, "live motion_publisher -> command -> /gazebo for %s "
                            "and joint_states -> robot_state_publisher; live edges now: %s"
                            % (cmds, sorted(g.live)))
            time.sleep(0.5)
        for node in ("/gazebo", mp, ns + "/robot_state_publisher", ns + "/controller_spawner"):
            self.assertIn(node, g.nodes)
        pub = publisher_of_the_simulator(g)
        for c in positions:
            state = "%s/%s/state" % (ns, c)
            self.assertTrue(g.has_edge(pub, state), "%s -> %s" % (pub, state))
            self.assertFalse(g.has_edge(mp, state))
        self.assertTrue(g.has_edge(pub, ns + "/joint_states"))
        self.assertIn((ns + "/joint_states", ns + "/robot_state_publisher", ""), g.live)
        self.assertTrue(g.has_edge(pub, "/clock"))
        nodes_only = build_graph(snapshot(), Options(mode="nodes"))
        for c in cmds:
            self.assertIn((mp, "/gazebo", c), nodes_only.live)


if __name__ == "__main__":
    rostest.rosrun("rqt_graph", "graph_scenario_check", GraphOfScenario)
