#!/usr/bin/env python3
"""rostest node for plot_step.test: `rosrun rqt_plot rqt_plot <state>/process_value
<state>/set_point --duration 5 --png --csv` (window under Xvfb) while `rosbag record` records
the same topic and a 1 rad step is commanded. Every plotted sample the bag also has carries the
same header stamp and values; one the bag lacks lies in a gap of the bag; the plot holds at
least 90 % of the bag's messages in its span (the publisher's per-connection queue of 10 can
drop under load); the span is 5 s of sim time and shows the step; the PNG is an image."""
import os
import shutil
import signal
import subprocess
import tempfile
import unittest

import rosbag
import rosgraph
import rospy
import rostest
from control_msgs.msg import JointControllerState
from std_msgs.msg import Float64

from rqt_plot.series import read_csv

from modrob_sim.waits import GraphWait, command_publisher, wait_until
from modrob_viz.render.xvfb import Xvfb

CTRL = "/ptrz/pan_position_controller"
STATE = CTRL + "/state"


def key(t):
    """A stamp in s as the comparison key: the CSV keeps 9 decimals, to_sec() may differ in the last bit."""
    return round(t, 6)


def connected_to(topic):
    """Nodes subscribed to ``topic`` with a live connection to its publisher (wherever /gazebo
    publishes it from: rospy or its roscpp side)."""
    graph = GraphWait(rosgraph.Master("/plot_step_check"), subscribe=None)
    return graph.connected_subscribers(topic)


class PlotMatchesBag(unittest.TestCase):
    def test_plot_of_a_step_matches_rosbag(self):
        rospy.init_node("plot_step_check")
        # connected before the step is published: the step lands where the plot expects it
        cmd = command_publisher(CTRL + "/command", Float64, 60)
        tmp = tempfile.mkdtemp(prefix="plot_step_")
        self.addCleanup(shutil.rmtree, tmp, ignore_errors=True)
        bag_path, csv_path, png_path = (os.path.join(tmp, n) for n in ("state.bag", "plot.csv", "plot.png"))
        with Xvfb(1280, 1024):
            bag = subprocess.Popen(["rosbag", "record", "-O", bag_path, "__name:=plot_bag", STATE],
                                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            plot = subprocess.Popen(["rosrun", "rqt_plot", "rqt_plot", STATE + "/process_value",
                                     STATE + "/set_point", "--duration", "5", "--window", "10",
                                     "--csv", csv_path, "--png", png_path, "--title", "pan 1 rad step"],
                                    stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
            try:        # both start while the simulator does: they wait for the topic themselves
                rospy.wait_for_message(STATE, JointControllerState, timeout=60)
                wait_until(lambda: "/plot_bag" in connected_to(STATE) and
                           any(n.startswith("/rqt_plot") for n in connected_to(STATE)), 60,
                           "rosbag and rqt_plot connected to " + STATE, period=0.2)   # master queries
                rospy.sleep(0.5)                   # sim time: half a second before the step
                cmd.publish(Float64(1.0))
                out, err = plot.communicate(timeout=70)
            finally:
                if plot.poll() is None:
                    plot.kill()
                bag.send_signal(signal.SIGINT)
                bag.wait(30)
        # the rosbag script passes SIGINT on to its recorder and leaves without waiting for it:
        # the recorder closes the bag (state.bag.active -> state.bag) after that
        wait_until(lambda: os.path.exists(bag_path) and not os.path.exists(bag_path + ".active"), 30,
                   "rosbag record to close " + bag_path)
        self.assertEqual(plot.returncode, 0, "rqt_plot failed: %s %s" % (out, err))
        plotted = read_csv(csv_path)
        pv, sp = plotted[STATE + "/process_value"], plotted[STATE + "/set_point"]
        self.assertEqual([t for t, _ in pv], [t for t, _ in sp])
        recorded = {}
        with rosbag.Bag(bag_path) as b:
            for _, msg, _ in b.read_messages(topics=[STATE]):
                recorded.setdefault(key(msg.header.stamp.to_sec()), []).append(msg)
        self.assertGreater(len(pv), 100)
        self.assertGreaterEqual(pv[-1][0] - pv[0][0], 5.0 - 0.05, "span of the plot")
        self.assertLessEqual(pv[-1][0] - pv[0][0], 5.0, "--duration 5 keeps 5 s")
        first, last = max(key(pv[0][0]), min(recorded)), key(pv[-1][0])    # where both were listening
        both = [(key(t), v, s) for (t, v), (t2, s) in zip(pv, sp) if key(t) >= first]
        self.assertGreater(len(both), 100)
        # /gazebo publishes the state with queue_size=10 per connection: on a loaded machine either
        # listener can lose a burst. A plotted sample the bag lacks must then sit in a gap of the
        # bag (the plot invents nothing), and the plot must hold nearly all the bag has.
        stamps = sorted(recorded)
        period = sorted(b - a for a, b in zip(stamps, stamps[1:]))[len(stamps) // 2]
        gaps = [(a, b) for a, b in zip(stamps, stamps[1:]) if b - a > 1.5 * period]
        matched = 0
        for t, v, s in both:
            msgs = recorded.get(t)
            if msgs:
                self.assertIn((v, s), [(m.process_value, m.set_point) for m in msgs], "values at t=%.6f" % t)
                matched += 1
            else:
                self.assertTrue(any(a < t < b for a, b in gaps),
                                "plotted sample at t=%.6f is neither in the bag nor in a gap of it" % t)
        inside = sum(len(m) for t, m in recorded.items() if first <= t <= last)
        rospy.loginfo("bag: %d messages in the plotted span, plot: %d samples, %d in both; bag gaps %s",
                      inside, len(both), matched, gaps)
        self.assertGreaterEqual(matched, 0.9 * inside, "the plot lost more than 10 %% of the bag's messages")
        self.assertAlmostEqual(sp[0][1], 0.0, places=3)
        self.assertEqual(sp[-1][1], 1.0)
        self.assertLess(abs(pv[-1][1] - 1.0), 0.05, "the pan joint reached the step")
        with open(png_path, "rb") as f:
            self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")
        keep = os.path.join(os.environ.get("ROS_HOME", tmp), "rqt_plot_step.png")
        shutil.copy(png_path, keep)
        rospy.loginfo("plot: %s; %d samples over %.2f s match the bag", keep, len(pv), last - first)
        shutil.rmtree(tmp)


if __name__ == "__main__":
    rostest.rosrun("rqt_plot", "plot_step_check", PlotMatchesBag)
