#!/usr/bin/env python3
"""rostest node: two runs of the /gazebo node with the same seed give identical model and link
states after 2 s of simulated time (a falling pile of boxes hitting each other and an arm driven by
a joint effort); a third run with a different pose of one box differs (the comparison can fail)."""
import os
import subprocess
import sys
import unittest

import rosnode
import rospy
import rostest
from geometry_msgs.msg import Point, Vector3, Wrench

from modrob_sim.waits import wait_until

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from sim_helpers import Gazebo  # noqa: E402

SCRIPT = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))),
                      "scripts", "gazebo")


def run_once(seed, box3_x=0.05):
    node = subprocess.Popen([sys.executable, SCRIPT, "_paused:=true", "_real_time_factor:=0",
                             "_seed:=%d" % seed], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        gz = Gazebo()
        assert gz.spawn("ground", "ground.urdf").success
        assert gz.spawn("arm2", "arm2.urdf", x=-0.8).success
        pile = (("box1", 0.0, 0.11, 0.0), ("box2", 0.03, 0.45, 0.38), ("box3", box3_x, 0.8, 0.7))
        for name, x, z, qz in pile:
            r = gz.spawn(name, "box.urdf", x=x, z=z, qz=qz, qw=(1 - qz * qz) ** 0.5)
            assert r.success, r.status_message
        assert gz.apply_joint_effort(joint_name="shoulder", effort=2.0, start_time=rospy.Time(0),
                                     duration=rospy.Duration(1.0)).success
        assert gz.apply_body_wrench(body_name="box2::body", reference_frame="world",
                                    reference_point=Point(), wrench=Wrench(force=Vector3(3.0, 1.0, 0.0)),
                                    start_time=rospy.Time(0), duration=rospy.Duration(0.5)).success
        for _ in range(4):
            assert gz.step(steps=500).success
        out = {}
        for model in gz.get_world_properties().model_names:
            for link in gz.get_model_properties(model_name=model).body_names:
                s = gz.get_link_state(link_name="%s::%s" % (model, link), reference_frame="world").link_state
                p, q, v, w = s.pose.position, s.pose.orientation, s.twist.linear, s.twist.angular
                out["%s::%s" % (model, link)] = (p.x, p.y, p.z, q.x, q.y, q.z, q.w,
                                                 v.x, v.y, v.z, w.x, w.y, w.z)
        out["time"] = gz.sim_time()
        return out
    finally:
        node.terminate()
        node.wait(10)
        wait_until(lambda: "/gazebo" not in rosnode.get_node_names(), 10.0)


class SimDeterminism(unittest.TestCase):
    def test_same_seed_same_states_after_two_seconds(self):
        a = run_once(7)
        b = run_once(7)
        self.assertAlmostEqual(a["time"], 2.0, places=9)
        self.assertEqual(sorted(a), sorted(b))
        moved = a["box3::body"][2]
        self.assertLess(moved, 0.7, "box3 should have fallen onto the pile")
        for key in a:
            self.assertEqual(a[key], b[key], "run 2 differs at %s" % key)
        c = run_once(7, box3_x=0.051)
        self.assertNotEqual(a["box3::body"], c["box3::body"], "a different start must give different states")


if __name__ == "__main__":
    rospy.init_node("sim_determinism_test")
    rostest.rosrun("modrob_sim", "sim_determinism", SimDeterminism)
