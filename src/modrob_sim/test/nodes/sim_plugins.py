#!/usr/bin/env python3
"""rostest node: the plugin contract of /gazebo with a probe plugin: the spawn robot_namespace
reaches plugins without their own, before_step(t, dt) runs once per physics step at the step's
time, reset() on reset_simulation (random stream re-seeded), shutdown() on delete_model; an
unknown plugin file is only warned."""
import sys
import unittest

import rospy
import rostest
from std_msgs.msg import String

from modrob_sim.waits import wait_until

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from sim_helpers import Gazebo, Latest  # noqa: E402


def fields(msg):
    return dict(kv.split("=", 1) for kv in msg.data.split())


class SimPlugins(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.gz = Gazebo()
        cls.gz.pause_physics()

    def probe(self, model):
        latest = Latest("/probe/%s" % model, String)
        self.assertTrue(wait_until(lambda: latest.get() is not None, 10.0), "no report from the probe")
        return latest

    def test_namespace_updates_reset_shutdown(self):
        r = self.gz.spawn("p1", "probe.urdf", ns="/robotA", z=1.0)
        self.assertTrue(r.success, r.status_message)
        p1 = self.probe("p1")
        self.assertEqual(fields(p1.get())["ns"], "/robotA")
        self.assertEqual(fields(p1.get())["ctx_ns"], "/robotA")
        it0 = self.gz.iterations()
        step = self.gz.step(steps=100)
        self.assertTrue(step.success)
        self.assertTrue(wait_until(lambda: fields(p1.get())["updates"] == "100", 10.0), p1.get().data)
        # update(t, dt) of the last step ran at the time before that step
        self.assertAlmostEqual(float(fields(p1.get())["last_t"]), step.sim_time - 0.001, places=6)
        self.assertEqual(step.iterations, it0 + 100)
        first_random = fields(p1.get())["first_random"]
        self.gz.reset_simulation()
        self.assertTrue(wait_until(lambda: fields(p1.get())["state"] == "reset", 10.0), p1.get().data)
        # reset_simulation re-seeds the plugin's random stream: the same first draw again
        self.assertEqual(fields(p1.get())["first_random"], first_random)
        self.gz.delete_model(model_name="p1")
        self.assertTrue(wait_until(lambda: fields(p1.get())["state"] == "shutdown", 10.0), p1.get().data)

    def test_own_robot_namespace_wins(self):
        r = self.gz.spawn("p2", "probe_own_ns.urdf", ns="/robotB", x=2.0, z=1.0)
        self.assertTrue(r.success, r.status_message)
        self.assertEqual(fields(self.probe("p2").get())["ns"], "/own")


if __name__ == "__main__":
    rospy.init_node("sim_plugins_test")
    rostest.rosrun("modrob_sim", "sim_plugins", SimPlugins)
