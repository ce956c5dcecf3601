#!/usr/bin/env python3
"""rostest depth_camera.test: a depth camera 0.5 m up at the origin looking along +x (hfov 1.0 rad,
160x120) and a red box of 0.4 m centred at (2, 0, 0.5): its face is the plane x = 1.8 m."""
import math
import time
import unittest

import numpy as np
import rospy
import rostest
from sensor_msgs.msg import CameraInfo, Image, PointCloud2

W, H, HFOV = 160, 120, 1.0
F = W / (2.0 * math.tan(HFOV / 2.0))
CX, CY = (W + 1) / 2.0, (H + 1) / 2.0
FACE, CAMERA_Z = 1.8, 0.5
FRAME = "camera_depth_optical_frame"


def to_world(x, y, z):
    """The camera's optical frame (z along world +x, x along world -y, y along world -z) in the world."""
    return z, -x, CAMERA_Z - y


class Latest(object):
    def __init__(self, topic, cls):
        self.msg = None
        self.sub = rospy.Subscriber(topic, cls, self._store, queue_size=1, buff_size=2 ** 24)

    def _store(self, msg):
        self.msg = msg

    def wait(self, cond=lambda m: True, timeout=90.0):
        end = time.monotonic() + timeout
        while time.monotonic() < end and not rospy.is_shutdown():
            m = self.msg
            if m is not None and cond(m):
                return m
            time.sleep(0.05)
        raise AssertionError("no suitable message on %s within %.0f s" % (self.sub.name, timeout))


def depth_array(msg):
    return np.frombuffer(msg.data, "<f4").reshape(msg.height, msg.width)


def cloud_array(msg):
    dt = np.dtype({"names": ["x", "y", "z", "rgb"], "formats": ["<f4", "<f4", "<f4", "<u4"],
                   "offsets": [0, 4, 8, 16], "itemsize": msg.point_step})
    return np.frombuffer(msg.data, dt).reshape(msg.height, msg.width)


class DepthCamera(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.depth = Latest("/camera/depth/image_raw", Image)
        cls.points = Latest("/camera/depth/points", PointCloud2)
        cls.rgb = Latest("/camera/rgb/image_raw", Image)
        cls.depth_info = Latest("/camera/depth/camera_info", CameraInfo)
        centre = (H // 2, W // 2)
        cls.d = cls.depth.wait(lambda m: np.isfinite(depth_array(m)[centre]))
        cls.p = cls.points.wait(lambda m: np.isfinite(cloud_array(m)["z"][centre]))

    def test_depth_image_reads_the_face_distance(self):
        d = self.d
        self.assertEqual((d.width, d.height, d.encoding, d.header.frame_id), (W, H, "32FC1", FRAME))
        a = depth_array(d)
        face = a[H // 2 - 10:H // 2 + 10, W // 2 - 10:W // 2 + 10]       # inside the face (~32 px)
        rospy.loginfo("depth on the face: %.4f..%.4f m (expected %.3f)", face.min(), face.max(), FACE)
        self.assertTrue(np.all(np.abs(face - FACE) <= 0.01), "depth on the face %s..%s, not %.3f +- 0.01"
                        % (face.min(), face.max(), FACE))
        self.assertTrue(np.isnan(a[0, 0]), "the sky (nothing drawn) must be NaN beyond the cutoff")

    def test_cloud_points_land_on_the_face_and_the_ground(self):
        c = cloud_array(self.p)
        self.assertEqual((self.p.width, self.p.height, self.p.header.frame_id), (W, H, FRAME))
        self.assertEqual([f.name for f in self.p.fields], ["x", "y", "z", "rgb"])
        self.assertFalse(self.p.is_dense)
        face = c[H // 2 - 10:H // 2 + 10, W // 2 - 10:W // 2 + 10]
        wx, wy, wz = to_world(face["x"], face["y"], face["z"])
        self.assertTrue(np.all(np.abs(wx - FACE) <= 0.01), "cloud x on the face %s..%s" % (wx.min(), wx.max()))
        self.assertTrue(np.all(np.abs(wy) <= 0.2 + 0.01) and np.all(np.abs(wz - 0.5) <= 0.2 + 0.01))
        # the centre pixel's point: where the pinhole model puts the pixel on the face
        v, u = H // 2, W // 2
        p = c[v, u]
        self.assertAlmostEqual(float(p["x"]), (u - CX) * FACE / F, delta=0.01)
        self.assertAlmostEqual(float(p["y"]), (v - CY) * FACE / F, delta=0.01)
        red = (int(p["rgb"]) >> 16) & 255, (int(p["rgb"]) >> 8) & 255, int(p["rgb"]) & 255
        self.assertTrue(red[0] > 100 and red[1] < 60 and red[2] < 60, "the face's points are red: %s" % (red,))
        # the bottom rows see the ground: world height 0
        ground = c[H - 3:, :]
        g = ground["z"][np.isfinite(ground["z"])]
        self.assertGreater(g.size, W, "the bottom rows should see the ground plane")
        _wx, _wy, gz = to_world(ground["x"], ground["y"], ground["z"])
        gz = gz[np.isfinite(gz)]
        rospy.loginfo("ground points: height %.4f..%.4f m", gz.min(), gz.max())
        self.assertTrue(np.all(np.abs(gz) <= 0.01), "ground points at %s..%s, not 0 +- 0.01" % (gz.min(), gz.max()))

    def test_rgb_and_camera_infos(self):
        rgb = self.rgb.wait()
        self.assertEqual((rgb.width, rgb.height, rgb.encoding), (W, H, "rgb8"))
        info = self.depth_info.wait()
        self.assertAlmostEqual(info.K[0], F, places=3)
        self.assertEqual(info.header.frame_id, FRAME)


if __name__ == "__main__":
    rospy.init_node("check_depth_camera")
    rostest.rosrun("modrob_viz", "depth_camera", DepthCamera)
