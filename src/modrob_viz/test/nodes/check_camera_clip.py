#!/usr/bin/env python3
"""rostest: test/fixtures/camera_clip.world seen through the renderer the simulator runs. Both
cameras at (0, 0, 1) look along +x (hfov 1.0 rad, 320x240); green box 0.3 m ahead (left of
centre), red box 2 m ahead (centre), blue box 4 m ahead (right, lower). clip_cam (near 0.5, far 3)
must show only the red box, wide_cam (near 0.02, far 300) all three, each where the pinhole model
puts it."""
import math
import time
import unittest

import numpy as np
import rospy
import rostest
from sensor_msgs.msg import Image

W, H, HFOV = 320, 240, 1.0
F = W / (2.0 * math.tan(HFOV / 2.0))
# box: (colour channel, centre ahead x, sideways y, height above the camera z, half edge)
BOXES = {"green": (1, 0.3, 0.06, 0.04, 0.03), "red": (0, 2.0, 0.0, 0.0, 0.1),
         "blue": (2, 4.0, -0.8, -0.2, 0.15)}


def pixels(msg, colour):
    """(rows, columns) of the pixels of a saturated colour (the others dark)."""
    a = np.frombuffer(msg.data, np.uint8).reshape(msg.height, msg.width, 3).astype(int)
    ch = BOXES[colour][0]
    others = [c for c in range(3) if c != ch]
    mask = (a[..., ch] > 100) & (a[..., others[0]] < 60) & (a[..., others[1]] < 60)
    return np.nonzero(mask)


def predicted_uv(colour):
    """Pixel of the centre of the box's face towards the camera (pinhole, Gazebo's cx, cy)."""
    _, x, y, z, half = BOXES[colour]
    return (W + 1) / 2.0 - F * y / (x - half), (H + 1) / 2.0 - F * z / (x - half)


def seen(msg):
    return {c: len(pixels(msg, c)[1]) for c in BOXES}


def wait_image(topic, predicate, timeout=60.0):
    last = None
    end = time.monotonic() + timeout
    while time.monotonic() < end and not rospy.is_shutdown():
        try:
            last = rospy.wait_for_message(topic, Image, timeout=10.0)
        except rospy.ROSException:
            continue
        if predicate(last):
            return last
    return last


class CameraClip(unittest.TestCase):
    def test_1_wide_camera_sees_all_three_boxes(self):
        msg = wait_image("/wide_cam/image_raw", lambda m: min(seen(m).values()) >= 20)
        self.assertIsNotNone(msg, "no image on /wide_cam/image_raw")
        counts = seen(msg)
        rospy.loginfo("wide_cam: pixels per box %s", counts)
        for colour in BOXES:
            self.assertGreaterEqual(counts[colour], 20, "wide_cam does not show the %s box" % colour)
            rows, cols = pixels(msg, colour)
            u, v = (cols.min() + cols.max() + 1) / 2.0, (rows.min() + rows.max() + 1) / 2.0
            pu, pv = predicted_uv(colour)
            self.assertLess(abs(u - pu), 6.0, "%s box at column %.1f, pinhole model %.1f" % (colour, u, pu))
            self.assertLess(abs(v - pv), 6.0, "%s box at row %.1f, pinhole model %.1f" % (colour, v, pv))

    def test_2_clip_camera_drops_boxes_outside_near_far(self):
        def only_red(m):
            c = seen(m)
            return c["red"] >= 20 and c["green"] == 0 and c["blue"] == 0
        msg = wait_image("/clip_cam/image_raw", only_red)
        self.assertIsNotNone(msg, "no image on /clip_cam/image_raw")
        counts = seen(msg)
        rospy.loginfo("clip_cam: pixels per box %s", counts)
        self.assertGreaterEqual(counts["red"], 20, "the red box (2 m, inside near 0.5 .. far 3) is missing")
        self.assertEqual(counts["green"], 0, "the green box 0.3 m ahead is nearer than near = 0.5 m "
                                             "but drawn")
        self.assertEqual(counts["blue"], 0, "the blue box 4 m ahead is beyond far = 3 m but drawn")


if __name__ == "__main__":
    rospy.init_node("check_camera_clip")
    rostest.rosrun("modrob_viz", "check_camera_clip", CameraClip)
