#!/usr/bin/env python3
"""Two-robot Bulbs and Slides, judged from the simulator's own topics (not from the scenario's word):
the bulb that waited at the red tip rests in the hand-over cradle at some moment (modrob0 put it
there), then comes to rest inside the blue slide's channel (modrob1 carried it on), and the two arms'
skeletons never come closer than two module radii (/gazebo/link_states)."""
import sys
import threading
import time
import unittest

import numpy as np
import rospy
import rostest
from gazebo_msgs.msg import LinkStates, ModelStates

from modrob_motion.bulbs_and_slides.clearance import clearance, positions_by_model, skeleton, urdf_parents
from modrob_motion.bulbs_and_slides.layout import Layout, bulb_grasp_point
from modrob_motion.bulbs_and_slides.outcome import on_slide

ARMS_TOUCH = 0.10   # m, two module radii


class TwoRobots(unittest.TestCase):
    def test_hand_over_through_the_cradle_to_the_blue_slide_without_touching(self):
        rospy.init_node("bas_two_robots_check")
        layout = Layout.load("two_robots")
        bulb = rospy.get_param("~bulb", "bulb_0")
        budget = float(rospy.get_param("~timeout", 105.0))
        deadline = time.time() + budget
        models = ["modrob0", "modrob1"]
        parents = {}
        while time.time() < deadline and len(parents) < 2:
            for m in models:
                if m not in parents and rospy.has_param("/%s/robot_description" % m):
                    parents[m] = urdf_parents(rospy.get_param("/%s/robot_description" % m))
            time.sleep(0.1)
        self.assertEqual(sorted(parents), models, "the robots' descriptions never appeared")

        lock = threading.Lock()
        state = {"closest": (float("inf"), None, None), "link_samples": 0}

        def on_states(msg):
            if bulb in msg.name:
                i = msg.name.index(bulb)
                p, o, v = msg.pose[i].position, msg.pose[i].orientation, msg.twist[i].linear
                with lock:
                    state["pose"] = ((p.x, p.y, p.z), (o.x, o.y, o.z, o.w))
                    state["speed"] = (v.x ** 2 + v.y ** 2 + v.z ** 2) ** 0.5

        def on_links(msg):
            pos = positions_by_model(msg.name, [(q.position.x, q.position.y, q.position.z) for q in msg.pose],
                                     models)
            if not all(pos[m] for m in models):
                return
            d, na, nb = clearance(skeleton(parents["modrob0"], pos["modrob0"]),
                                  skeleton(parents["modrob1"], pos["modrob1"]))
            with lock:
                state["link_samples"] += 1
                if d < state["closest"][0]:
                    state["closest"] = (d, na, nb)

        rospy.Subscriber("/gazebo/model_states", ModelStates, on_states, queue_size=1)
        rospy.Subscriber("/gazebo/link_states", LinkStates, on_links, queue_size=1)
        cradle = np.asarray(layout.cradle_point)
        in_cradle_since = None
        was_in_cradle = False
        rest_since = None
        where = "never seen"
        done = False
        while time.time() < deadline and not done:
            time.sleep(0.05)
            with lock:
                if "pose" not in state:
                    continue
                pose, speed = state["pose"], state["speed"]
            c, _ = bulb_grasp_point(layout, pose)
            now = rospy.get_time()
            if np.linalg.norm(c - cradle) < 0.03 and speed < 0.005:
                in_cradle_since = in_cradle_since or now
                was_in_cradle = was_in_cradle or now - in_cradle_since > 0.3
            else:
                in_cradle_since = None
            s, lat, h = layout.slides["blue_slide"].coordinates(c)
            where = "along %.3f, across %.3f, height %.3f m of the blue slide" % (s, lat, h)
            if on_slide(layout, "blue_slide", c) and speed < 0.005:
                rest_since = rest_since or now
                done = now - rest_since > 1.0
            else:
                rest_since = None
        with lock:
            closest, samples = state["closest"], state["link_samples"]
        self.assertTrue(was_in_cradle, "%s never rested in the hand-over cradle at (%.3f, %.3f, %.3f)"
                        % ((bulb,) + tuple(cradle)))
        self.assertTrue(done, "%s did not come to rest on the blue slide within %.0f s (last: %s)"
                        % (bulb, budget, where))
        self.assertGreater(samples, 100, "too few /gazebo/link_states to judge the arms' clearance")
        self.assertGreater(closest[0], ARMS_TOUCH, "the arms came within %.0f mm (modrob0 %s, modrob1 %s)"
                           % (1000 * closest[0], closest[1], closest[2]))
        rospy.loginfo("bas_two_robots: bulb via the cradle onto the blue slide; arms' closest approach "
                      "%.0f mm", 1000 * closest[0])


if __name__ == "__main__":
    rostest.rosrun("modrob_motion", "bas_two_robots", TwoRobots, sys.argv)
