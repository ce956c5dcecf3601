#!/usr/bin/env python3
"""rostest node: gazebo_ros's launch files as modrob_sim has them. shapes_world.launch (gui fixed
to true, as gazebo_ros writes it) comes up on a machine without a display: the GUI warns once and
stays away, the simulation runs with the world's three shapes; gzclient itself, started without a
display, says so and exits cleanly; with one (a private Xvfb) it runs RViz as its child in a
process group of its own and a stop as roslaunch sends it (SIGINT to gzclient's group) ends both
with exit code 0."""
import os
import select
import signal
import subprocess
import sys
import time
import unittest

import rosnode
import rospy
import rostest
from rosgraph_msgs.msg import Clock

from modrob_sim.procs import proc_stat
from modrob_sim.waits import wait_until

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sim_helpers import Gazebo, Latest  # noqa: E402


class SimGazeboRosLaunches(unittest.TestCase):
    def test_shapes_world_runs_headless_with_gui_true(self):
        gz = Gazebo()
        names = gz.get_world_properties().model_names
        self.assertEqual(sorted(names), ["box", "cylinder", "ground_plane", "sphere"])
        clock = Latest("/clock", Clock)
        self.assertTrue(wait_until(lambda: clock.get() is not None, 20.0), "no /clock")
        first = clock.get().clock
        self.assertTrue(wait_until(lambda: clock.get().clock.to_sec() > first.to_sec() + 0.5, 30.0),
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

    def test_gzclient_runs_rviz_as_its_child_and_stops_cleanly(self):
        read, write = os.pipe()
        xvfb = subprocess.Popen(["Xvfb", "-displayfd", str(write), "-screen", "0", "800x600x24",
                                 "-nolisten", "tcp"], pass_fds=[write], stdout=subprocess.DEVNULL,
                                stderr=subprocess.DEVNULL)
        os.close(write)
        with os.fdopen(read) as f:
            number = f.readline().strip()
        self.assertTrue(number, "Xvfb did not start")
        env = dict(os.environ, DISPLAY=":" + number)
        gz = subprocess.Popen(["rosrun", "modrob_sim", "gzclient", "__name:=gzclient_gui_probe"], env=env,
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, start_new_session=True)
        try:
            up = wait_until(lambda: "/gzclient_gui_probe" in rosnode.get_node_names()
                            or gz.poll() is not None, 60.0)
            self.assertTrue(up and gz.poll() is None, "RViz did not come up as /gzclient_gui_probe "
                            "(gzclient ended with %s)" % gz.poll())
            pids = [int(p) for p in os.listdir("/proc") if p.isdigit()]
            rviz = [pid for pid in pids if (proc_stat(pid) or (0, 0, 0))[2] == gz.pid]
            self.assertEqual(len(rviz), 1, "gzclient %d has no one child process" % gz.pid)
            self.assertIn("rviz", proc_stat(rviz[0])[0])
            self.assertNotEqual(proc_stat(rviz[0])[3], gz.pid, "RViz is in gzclient's process group")
            os.killpg(gz.pid, signal.SIGINT)                 # as roslaunch stops a node
            self.assertEqual(gz.wait(30), 0)
            out = read_to_end(gz.stdout, 30)
            self.assertEqual([x for x in out.splitlines() if x.startswith("gzclient:") and
                              "while stopping (a known RViz/Mesa crash at exit); ignored" not in x], [], out)
        finally:
            if gz.poll() is None:
                os.killpg(gz.pid, signal.SIGKILL)
                gz.wait()
            gz.stdout.close()
            xvfb.terminate()
            xvfb.wait()


def read_to_end(pipe, timeout):
    """Everything written to ``pipe`` until EOF (every process holding it has ended)."""
    end, out = time.monotonic() + timeout, b""
    while True:
        left = end - time.monotonic()
        if left <= 0 or not select.select([pipe], [], [], left)[0]:
            raise AssertionError("output still open after %.0f s (a process outlived gzclient?):\n%s"
                                 % (timeout, out.decode(errors="replace")))
        chunk = os.read(pipe.fileno(), 4096)
        if not chunk:
            return out.decode(errors="replace")
        out += chunk


if __name__ == "__main__":
    rospy.init_node("sim_gazebo_ros_launches_test")
    rostest.rosrun("modrob_sim", "sim_gazebo_ros_launches", SimGazeboRosLaunches)
