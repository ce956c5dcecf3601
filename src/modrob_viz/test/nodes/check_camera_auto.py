#!/usr/bin/env python3
"""rostest camera_auto.test: the simulator runs the camera renderer only while a camera is
subscribed. Camera 0.5 m up at the origin looking along +x (hfov 1.0 rad, 160x120); red box of
0.4 m centred at (2, 0, 0.5)."""
import math
import time
import unittest
from xmlrpc.client import ServerProxy

import numpy as np
import rosgraph
import rospy
import rostest
import rostopic
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import CameraInfo, Image

RENDERER = "/gazebo_camera_renderer"
W, H, HFOV = 160, 120, 1.0
F = W / (2.0 * math.tan(HFOV / 2.0))


def renderer_running():
    """The renderer node is registered and answers (a stopped one may leave its registration)."""
    try:
        uri = rosgraph.Master("/check_camera_auto").lookupNode(RENDERER)
        ServerProxy(uri).getPid("/check_camera_auto")
        return True
    except (rosgraph.MasterError, OSError):
        return False


def wait_for(cond, timeout, what):
    end = time.monotonic() + timeout
    while time.monotonic() < end and not rospy.is_shutdown():
        if cond():
            return
        time.sleep(0.05)
    raise AssertionError("no %s within %.0f s" % (what, timeout))


def red_pixels(msg):
    a = np.frombuffer(msg.data, np.uint8).reshape(msg.height, msg.width, 3).astype(int)
    return np.nonzero((a[..., 0] > 100) & (a[..., 1] < 60) & (a[..., 2] < 60))


class CameraAuto(unittest.TestCase):
    def test_renderer_runs_while_subscribed(self):
        # the box and the camera spawned, and 3 s of simulated time with nobody subscribed
        wait_for(lambda: rospy.get_param("/gazebo/camera_sensors", {}), 60.0, "camera sensor registered")
        t0 = rospy.wait_for_message("/clock", Clock, 30.0).clock.to_sec()
        wait_for(lambda: rospy.get_time() > t0 + 3.0, 60.0, "3 s of simulated time")
        self.assertFalse(renderer_running(), "a renderer runs although nobody subscribes to a camera")
        # advertised all the same (by /gazebo, as gzserver does): rostopic echo/hz can subscribe
        for topic, kind in (("/camera/rgb/image_raw", "sensor_msgs/Image"),
                            ("/camera/rgb/camera_info", "sensor_msgs/CameraInfo")):
            self.assertEqual(rostopic.get_topic_type(topic)[0], kind)

        frames = []
        sub = rospy.Subscriber("/camera/rgb/image_raw", Image, frames.append, queue_size=1)
        wait_for(lambda: frames and len(red_pixels(frames[-1])[0]) > 0, 90.0, "image showing the red box")
        self.assertTrue(renderer_running())
        msg = frames[-1]
        self.assertEqual((msg.width, msg.height, msg.encoding), (W, H, "rgb8"))
        self.assertEqual(msg.header.frame_id, "camera_rgb_optical_frame")
        info = rospy.wait_for_message("/camera/rgb/camera_info", CameraInfo, 30.0)
        self.assertAlmostEqual(info.K[0], F, places=3)
        rows, cols = red_pixels(msg)
        # the face at x = 1.8 spans 0.4 m: F * 0.4 / 1.8 px, centred on the principal point
        size = F * 0.4 / 1.8
        rospy.loginfo("red box: %d px, columns %d..%d, rows %d..%d (predicted %.1f px wide)",
                      len(rows), cols.min(), cols.max(), rows.min(), rows.max(), size)
        self.assertAlmostEqual(cols.max() - cols.min() + 1, size, delta=3)
        self.assertAlmostEqual(rows.max() - rows.min() + 1, size, delta=3)
        # the box's middle on the principal point of the CameraInfo ((W + 1) / 2, (H + 1) / 2)
        self.assertAlmostEqual(cols.mean(), info.K[2], delta=0.75)
        self.assertAlmostEqual(rows.mean(), info.K[5], delta=0.75)

        sub.unregister()
        wait_for(lambda: not renderer_running(), 30.0, "renderer stopped after the last subscriber left")


if __name__ == "__main__":
    rospy.init_node("check_camera_auto")
    rostest.rosrun("modrob_viz", "camera_auto", CameraAuto)
