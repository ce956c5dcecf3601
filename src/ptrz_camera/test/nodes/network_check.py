#!/usr/bin/env python3
"""rostest node of network.test: ptrz.launch cameras:=3 (indoor, renderer on): every camera
publishes images, each camera moves without moving the others, the live zoom refuses a field of
view outside the camera's range, and halving the field of view doubles an object's size in
image_raw (+-5 %, the cyan top of robot_cyan_1, with camera_info following)."""
import math
import os
import sys
import unittest

import cv2
import numpy as np
import rospy
import rostest
from rosgraph_msgs.msg import Log
from sensor_msgs.msg import CameraInfo, Image
from std_msgs.msg import Float64

from modrob_sim.waits import Latest, wait_running, wait_until

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ptrz_test_common import CONTROLLERS, Joints  # noqa: E402

from ptrz_camera import kinematics  # noqa: E402

CAMS = ["ptrz1", "ptrz2", "ptrz3"]
CYAN_TOP = (5.1, 1.2, 0.64)           # robot_cyan_1's top disc (inside_world.world)


def cyan_width(msg):
    """Width (px) of the cyan blob nearest the image centre (the robot's top disc)."""
    img = np.frombuffer(msg.data, np.uint8).reshape(msg.height, msg.width, 3).astype(int)
    mask = ((img[..., 2] > 110) & (img[..., 1] > 110) & (img[..., 0] < 100)
            & (np.abs(img[..., 1] - img[..., 2]) < 70)).astype(np.uint8)
    n, labels, stats, centroids = cv2.connectedComponentsWithStats(mask, 8)
    if n <= 1:
        return 0
    centre = np.array([msg.width / 2.0, msg.height / 2.0])
    best = 1 + int(np.argmin(np.linalg.norm(centroids[1:] - centre, axis=1)))
    return int(stats[best, cv2.CC_STAT_WIDTH])


class Network(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("network_check")
        for ns in CAMS:
            wait_running("/" + ns, CONTROLLERS)
        cls.joints = {ns: Joints("/" + ns) for ns in CAMS}
        cls.images = {ns: Latest("/%s/camera1/image_raw" % ns, Image, queue_size=1, buff_size=2 ** 24)
                      for ns in CAMS}
        cls.infos = {ns: Latest("/%s/camera1/camera_info" % ns, CameraInfo) for ns in CAMS}
        cls.cmd = {(ns, j): rospy.Publisher("/%s/%s_position_controller/command" % (ns, j), Float64,
                                            queue_size=1,
                                            latch=True) for ns in CAMS for j in ("pan", "tilt")}
        cls.zoom = rospy.Publisher("/ptrz1/zoom", Float64, queue_size=1, latch=True)
        cls.zoom_fov = Latest("/ptrz1/zoom_fov", Float64)
        cls.rosout = Latest("/rosout", Log, keep=True)      # connected to every node's long before test_3

    def test_1_every_camera_publishes_images(self):
        wait_until(lambda: all(self.images[ns].msg is not None for ns in CAMS), 80,
                   "images of all three cameras")
        for ns in CAMS:
            self.assertEqual((self.images[ns].msg.width, self.images[ns].msg.height), (320, 128))

    def test_2_each_camera_moves_alone(self):
        before = {ns: self.joints[ns].position("pan") for ns in CAMS}
        self.cmd[("ptrz2", "pan")].publish(Float64(0.8))
        wait_until(lambda: abs(self.joints["ptrz2"].position("pan") - 0.8) < 0.02, 60, "ptrz2 pan at 0.8")
        for ns in ("ptrz1", "ptrz3"):
            self.assertAlmostEqual(self.joints[ns].position("pan"), before[ns], delta=1e-3)

    def test_3_zoom_outside_the_range_is_refused(self):
        wait_until(lambda: self.zoom_fov.msg is not None, 30, "/ptrz1/zoom_fov")
        start = self.zoom_fov.msg.data
        self.zoom.publish(Float64(3.05))                 # wider than the camera's 2.79 rad
        # the zoom node has taken it (its warning), and its field of view stays
        wait_until(lambda: [m for m in self.rosout.history if m.msg.startswith("/ptrz1/zoom: ")
                            and "3.05" in m.msg and "; keeping %.4f rad" % start in m.msg],
                   30, "the zoom node's warning that refuses 3.05 rad")
        self.assertEqual(self.zoom_fov.msg.data, start)

    def test_4_halving_the_field_of_view_doubles_the_size(self):
        chain = kinematics.CameraChain(rospy.get_param("/ptrz1/robot_description"))
        pan, tilt = chain.aim(CYAN_TOP, {})
        self.cmd[("ptrz1", "pan")].publish(Float64(pan))
        self.cmd[("ptrz1", "tilt")].publish(Float64(tilt))
        wait_until(lambda: abs(self.joints["ptrz1"].position("pan") - pan) < 0.005
                   and abs(self.joints["ptrz1"].position("tilt") - tilt) < 0.005,
                   60, "ptrz1 aimed at robot_cyan_1")
        sizes = []
        for fov in (0.5, 0.25):
            self.zoom.publish(Float64(fov))
            f_expected = 320 / (2 * math.tan(fov / 2))
            info = self.infos["ptrz1"].wait(lambda m: abs(m.K[0] - f_expected) < 0.01, 60,
                                            "camera_info at fov %.2f" % fov)
            # an image rendered half a simulated second after the new field of view (by its stamp:
            # the one taken last can be older than the camera_info just read)
            sizes.append(cyan_width(self.images["ptrz1"].after(info.header.stamp.to_sec() + 0.5, 30)))
        rospy.loginfo("cyan top width: %s px" % sizes)
        self.assertGreater(sizes[0], 8)
        self.assertAlmostEqual(sizes[1] / float(sizes[0]), 2.0, delta=0.1)


if __name__ == "__main__":
    rostest.rosrun("ptrz_camera", "network", Network)
