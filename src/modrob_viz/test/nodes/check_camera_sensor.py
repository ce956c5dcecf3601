#!/usr/bin/env python3
"""rostest: the camera sensor of test/fixtures/camera_box.world (camera at (0,0,1) looking along
+x, hfov 1.0 rad, 320x240; red box of 0.2 m centred at (2,0,1)) seen through camera_renderer."""
import math
import time
import unittest

import numpy as np
import rospy
import rostest
from sensor_msgs.msg import CameraInfo, Image
from std_msgs.msg import Float64

IMAGE, INFO = "/test_cam/image_raw", "/test_cam/camera_info"
W, H, HFOV = 320, 240, 1.0
BOX_NEAR, HALF = 1.9, 0.1     # distance of the box's front face [m], half its edge [m]


def red_box(msg):
    a = np.frombuffer(msg.data, np.uint8).reshape(msg.height, msg.width, 3).astype(int)
    mask = (a[..., 0] > 100) & (a[..., 1] < 60) & (a[..., 2] < 60)
    ys, xs = np.nonzero(mask)
    if len(xs) < 10:
        return None
    return dict(u=(xs.min() + xs.max() + 1) / 2.0, v=(ys.min() + ys.max() + 1) / 2.0,
                width=xs.max() - xs.min() + 1, height=ys.max() - ys.min() + 1)


def wait_image(predicate, timeout=60.0):
    last = None
    end = time.monotonic() + timeout
    while time.monotonic() < end and not rospy.is_shutdown():
        try:
            msg = rospy.wait_for_message(IMAGE, Image, timeout=10.0)
        except rospy.ROSException:
            continue
        last = msg
        if predicate(msg):
            return msg
    return last


class CameraSensor(unittest.TestCase):
    def test_pinhole_zoom_and_camera_info(self):
        info = rospy.wait_for_message(INFO, CameraInfo, timeout=60.0)
        f = W / (2.0 * math.tan(HFOV / 2.0))
        self.assertAlmostEqual(info.K[0], f, places=6)
        self.assertAlmostEqual(info.K[4], f, places=6)
        self.assertEqual((info.K[2], info.K[5]), ((W + 1) / 2.0, (H + 1) / 2.0))
        self.assertEqual(info.header.frame_id, "camera_link_optical")
        msg = wait_image(lambda m: red_box(m) is not None)
        self.assertIsNotNone(msg, "no image on %s" % IMAGE)
        self.assertEqual((msg.width, msg.height, msg.encoding), (W, H, "rgb8"))
        box = red_box(msg)
        self.assertIsNotNone(box, "the red box is not in the image")
        size = 2 * f * HALF / BOX_NEAR
        rospy.loginfo("box %s, predicted centre (%.1f, %.1f) size %.1f", box, info.K[2], info.K[5], size)
        self.assertLess(abs(box["u"] - W / 2.0), 3.0)
        self.assertLess(abs(box["v"] - H / 2.0), 3.0)
        self.assertLess(abs(box["width"] - size), 3.0)
        self.assertLess(abs(box["height"] - size), 3.0)

        # zoom: half the tangent of the half angle = twice the focal length = twice the size
        new_hfov = 2.0 * math.atan(math.tan(HFOV / 2.0) / 2.0)
        pub = rospy.Publisher("/test_cam/set_hfov", Float64, queue_size=1, latch=True)
        pub.publish(Float64(new_hfov))
        zoomed = wait_image(lambda m: (red_box(m) or {}).get("width", 0) > 1.5 * size)
        big = red_box(zoomed) if zoomed is not None else None
        self.assertIsNotNone(big, "no zoomed image")
        self.assertLess(abs(big["width"] - 2 * size), 3.0,
                        "zoomed box %s, expected width %.1f" % (big, 2 * size))
        self.assertLess(abs(big["u"] - W / 2.0), 3.0)
        info2 = rospy.wait_for_message(INFO, CameraInfo, timeout=10.0)
        self.assertAlmostEqual(info2.K[0], 2 * f, places=4)


if __name__ == "__main__":
    rospy.init_node("check_camera_sensor")
    rostest.rosrun("modrob_viz", "check_camera_sensor", CameraSensor)
