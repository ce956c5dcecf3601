#!/usr/bin/env python3
"""The pick-and-place succeeds: the bulb that waited at the red slide's tip comes to rest inside the
blue slide's channel (read from /gazebo/model_states, judged with the world's layout numbers)."""
import sys
import time
import unittest

import rospy
import rostest
from gazebo_msgs.msg import ModelStates

from modrob_motion.bulbs_and_slides.layout import Layout, bulb_grasp_point
from modrob_motion.bulbs_and_slides.outcome import on_slide


class PickAndPlace(unittest.TestCase):
    def test_bulb_ends_on_the_blue_slide(self):
        rospy.init_node("bas_pick_place_check")
        layout = Layout.load(rospy.get_param("~scenario", "one_robot"))
        bulb = rospy.get_param("~bulb", "bulb_0")
        state = {}

        def on_states(msg):
            if bulb in msg.name:
                i = msg.name.index(bulb)
                p, o, v = msg.pose[i].position, msg.pose[i].orientation, msg.twist[i].linear
                state["pose"] = ((p.x, p.y, p.z), (o.x, o.y, o.z, o.w))
                state["speed"] = (v.x ** 2 + v.y ** 2 + v.z ** 2) ** 0.5
        rospy.Subscriber("/gazebo/model_states", ModelStates, on_states, queue_size=1)
        deadline = time.time() + 85
        rest_since = None
        where = "never seen"
        while time.time() < deadline:
            time.sleep(0.05)
            if "pose" not in state:
                continue
            c, _ = bulb_grasp_point(layout, state["pose"])
            s, lat, h = layout.slides["blue_slide"].coordinates(c)
            where = "along %.3f, across %.3f, height %.3f m of the blue slide" % (s, lat, h)
            if on_slide(layout, "blue_slide", c) and state["speed"] < 0.005:
                rest_since = rest_since or rospy.get_time()
                if rospy.get_time() - rest_since > 1.0:
                    return
            else:
                rest_since = None
        self.fail("%s did not come to rest on the blue slide (last: %s)" % (bulb, where))


if __name__ == "__main__":
    rostest.rosrun("modrob_motion", "bas_pick_place", PickAndPlace, sys.argv)
