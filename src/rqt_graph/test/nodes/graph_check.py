#!/usr/bin/env python3
"""rostest node for graph_ptrz.test: the graph of the running PTRZ system has /gazebo, the
spawned controllers' command/state topics, robot_state_publisher and the commander, with the
edges their registrations and live connections give (and none that do not exist); `rosrun
rqt_graph rqt_graph -o x.png -o x.svg` writes real images; the window shows the graph under Xvfb
(screenshot in $ROS_HOME/test_output). The simulator's topics are published by /gazebo_roscpp, its
roscpp side, when it publishes through roscpp (its default, docs/simulator.md), by /gazebo otherwise."""
import os
import subprocess
import tempfile
import time
import unittest

import rospkg
import rospy
import rostest

from rqt_graph.graph_model import Options, build_graph, parse_dot_edges, to_dot
from rqt_graph.ros_graph import snapshot

from modrob_viz.render.xvfb import Xvfb

CONTROLLERS = ("pan", "tilt", "roll")
PAN_CMD = "/ptrz/pan_position_controller/command"


def publisher_of_the_simulator(graph):
    return "/gazebo_roscpp" if "/gazebo_roscpp" in graph.nodes else "/gazebo"


def wait_graph(pred, timeout, what, opts=None):
    """The first graph (default options) for which ``pred(graph)`` holds."""
    deadline = time.monotonic() + timeout
    while True:
        graph = build_graph(snapshot(), opts or Options())
        if pred(graph):
            return graph
        if time.monotonic() > deadline or rospy.is_shutdown():
            raise AssertionError("timed out after %.0f s waiting for %s; nodes %s, edges %s"
                                 % (timeout, what, graph.nodes, graph.edges))
        time.sleep(0.3)


class GraphOfPtrz(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("graph_check")
        rospy.wait_for_service("/ptrz/roll_position_controller/pid/set_parameters", timeout=60)

    def test_1_nodes_topics_and_edges(self):
        g = wait_graph(lambda g: (PAN_CMD, "/gazebo", "") in g.live and
                       (publisher_of_the_simulator(g), "/ptrz/joint_states", "") in g.live, 40,
                       "live connections commander -> command -> /gazebo -> joint_states")
        pub = publisher_of_the_simulator(g)
        for node in ("/gazebo", "/robot_state_publisher", "/ptrz/controller_spawner", "/ptrz/pan_commander"):
            self.assertIn(node, g.nodes)
        self.assertNotIn("/rosout", g.nodes)                       # debug hidden by default
        for c in CONTROLLERS:
            cmd, state = "/ptrz/%s_position_controller/command" % c, "/ptrz/%s_position_controller/state" % c
            self.assertIn(cmd, g.topics)
            self.assertIn(state, g.topics)
            self.assertTrue(g.has_edge(cmd, "/gazebo"), "%s -> /gazebo" % cmd)
            self.assertTrue(g.has_edge(pub, state), "%s -> %s" % (pub, state))
            self.assertFalse(g.has_edge(pub, cmd), "%s does not publish %s" % (pub, cmd))
        expected = [("/ptrz/pan_commander", PAN_CMD), (pub, "/clock"),
                    ("/clock", "/robot_state_publisher"),
                    (pub, "/ptrz/joint_states"), ("/ptrz/joint_states", "/robot_state_publisher"),
                    ("/robot_state_publisher", "/tf"), ("/robot_state_publisher", "/tf_static")]
        for src, dst in expected:
            self.assertTrue(g.has_edge(src, dst), "%s -> %s" % (src, dst))
        self.assertIn(("/ptrz/pan_commander", PAN_CMD, ""), g.live)
        self.assertFalse(g.has_edge("/robot_state_publisher", "/ptrz/joint_states"))
        # the tilt command topic has a subscriber (/gazebo) but nobody publishes: a dead sink
        hidden = build_graph(snapshot(), Options(hide_dead_sinks=True))
        self.assertNotIn("/ptrz/tilt_position_controller/command", hidden.topics)
        self.assertIn(PAN_CMD, hidden.topics)

    def test_2_nodes_only_mode_uses_live_connections(self):
        opts = Options(mode="nodes")
        g = wait_graph(lambda g: ("/ptrz/pan_commander", "/gazebo", PAN_CMD) in g.live, 40,
                       "the commander -> /gazebo connection", opts)
        self.assertIn((publisher_of_the_simulator(g), "/robot_state_publisher", "/ptrz/joint_states"), g.live)
        self.assertEqual(g.topics, [])

    def test_3_namespaces_group_into_clusters(self):
        opts = Options(group_namespaces=True)
        dot = to_dot(build_graph(snapshot(), opts), opts)
        ptrz = dot.index('subgraph "cluster_/ptrz" {')
        pan = dot.index('subgraph "cluster_/ptrz/pan_position_controller" {')
        self.assertLess(ptrz, pan)
        self.assertIn('"t:%s" [label="command"' % PAN_CMD, dot[pan:])
        self.assertIn(("/ptrz/pan_commander", PAN_CMD), parse_dot_edges(dot))

    def test_4_command_line_writes_png_and_svg(self):
        with tempfile.TemporaryDirectory() as tmp:
            png, svg = os.path.join(tmp, "g.png"), os.path.join(tmp, "g.svg")
            proc = subprocess.run(["rosrun", "rqt_graph", "rqt_graph", "-o", png, "-o", svg,
                                   "--group-namespaces"], capture_output=True, text=True, timeout=60)
            self.assertEqual(proc.returncode, 0, proc.stderr)
            with open(png, "rb") as f:
                self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")
            with open(svg) as f:
                text = f.read()
            self.assertIn("<svg", text)
            self.assertIn("n:/gazebo", text)
            self.assertIn("t:%s" % PAN_CMD, text)
            bad = subprocess.run(["rosrun", "rqt_graph", "rqt_graph", "-o", os.path.join(tmp, "g.jpeg")],
                                 capture_output=True, text=True, timeout=60)
            self.assertEqual(bad.returncode, 2)
            self.assertIn("output '%s' must end in one of" % os.path.join(tmp, "g.jpeg"), bad.stderr)

    def test_5_window_under_xvfb(self):
        with Xvfb(1280, 1024):
            from PyQt5 import QtWidgets
            from rqt_graph.graph_window import GraphWindow
            app = QtWidgets.QApplication.instance() or QtWidgets.QApplication(["graph_check"])
            window = GraphWindow(snapshot, Options(group_namespaces=True))
            window.show()
            window.refresh()
            app.processEvents()
            self.assertRegex(window.status.text(), r"^\d+ nodes, \d+ topics, \d+ edges")
            self.assertFalse(window.image.pixmap().isNull())
            self.assertIn("cluster_/ptrz", window.dot_text)
            window.checks["group_namespaces"].setChecked(False)
            self.assertNotIn("cluster_", window.dot_text)
            window.checks["group_namespaces"].setChecked(True)
            app.processEvents()
            out = os.path.join(rospkg.get_ros_home(), "test_output", "rqt_graph_window.png")
            os.makedirs(os.path.dirname(out), exist_ok=True)
            self.assertTrue(window.grab().save(out))
            rospy.loginfo("screenshot: %s", out)
            window.close()


if __name__ == "__main__":
    rostest.rosrun("rqt_graph", "graph_check", GraphOfPtrz)
