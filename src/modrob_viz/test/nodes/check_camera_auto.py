#!/usr/bin/env python3
"""rostest camera_auto.test: the simulator runs the camera renderer only while a camera is
subscribed, a depth camera's outputs are exact to the geometry, and gazebo_plugins' other cameras
(stereo pair, triggered, lens distortion, 16-bit and bayer formats: fixtures/camera_family.urdf)
publish as theirs do.

A depth camera (libgazebo_ros_openni_kinect.so, TurtleBot3 waffle's topic names) 0.5 m up at the
origin looking along +x (hfov 1.0 rad, 160x120); a red box of 0.4 m centred at (2, 0, 0.5): its
face is the plane x = 1.8 m. The tests run in name order on one simulator and one renderer start
(a renderer's start-up is most of a camera test's time)."""
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
from sensor_msgs.msg import CameraInfo, Image, PointCloud2
from std_msgs.msg import Empty

RENDERER = "/gazebo_camera_renderer"
W, H, HFOV = 160, 120, 1.0
F = W / (2.0 * math.tan(HFOV / 2.0))
CX, CY = (W + 1) / 2.0, (H + 1) / 2.0
FACE, CAMERA_Z, HALF = 1.8, 0.5, 0.2
FRAME = "camera_depth_optical_frame"
TOPICS = (("/camera/rgb/image_raw", Image), ("/camera/rgb/camera_info", CameraInfo),
          ("/camera/depth/image_raw", Image), ("/camera/depth/camera_info", CameraInfo),
          ("/camera/depth/points", PointCloud2),
          ("/stereo/left/image_raw", Image), ("/stereo/left/camera_info", CameraInfo),
          ("/stereo/right/image_raw", Image), ("/stereo/right/camera_info", CameraInfo),
          ("/trig/image_raw", Image), ("/lens/image_raw", Image), ("/lens/camera_info", CameraInfo))


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


class Latest(object):
    def __init__(self, topic, cls):
        self.msg = None
        self.count = 0
        self.sub = rospy.Subscriber(topic, cls, self._store, queue_size=1, buff_size=2 ** 24)

    def _store(self, msg):
        self.count += 1
        self.msg = msg

    def wait(self, cond=lambda m: True, timeout=90.0):
        found = []

        def ready():
            m = self.msg
            if m is not None and cond(m):
                found.append(m)
            return bool(found)
        wait_for(ready, timeout, "suitable message on %s" % self.sub.name)
        return found[0]


def red_pixels(msg):
    a = np.frombuffer(msg.data, np.uint8).reshape(msg.height, msg.width, 3).astype(int)
    return np.nonzero((a[..., 0] > 100) & (a[..., 1] < 60) & (a[..., 2] < 60))


def depth_array(msg):
    return np.frombuffer(msg.data, "<f4").reshape(msg.height, msg.width)


def cloud_array(msg):
    dt = np.dtype({"names": ["x", "y", "z", "rgb"], "formats": ["<f4", "<f4", "<f4", "<u4"],
                   "offsets": [0, 4, 8, 16], "itemsize": msg.point_step})
    return np.frombuffer(msg.data, dt).reshape(msg.height, msg.width)


def to_world(x, y, z):
    """The camera's optical frame (z along world +x, x along world -y, y along world -z) in the world."""
    return z, -x, CAMERA_Z - y


class CameraAuto(unittest.TestCase):
    subs = {}

    def test_1_nothing_runs_while_unsubscribed(self):
        # the box and the camera spawned, and 2 s of simulated time with nobody subscribed
        wait_for(lambda: rospy.get_param("/gazebo/camera_sensors", {}), 60.0, "camera sensor registered")
        t0 = rospy.wait_for_message("/clock", Clock, 30.0).clock.to_sec()
        wait_for(lambda: rospy.get_time() > t0 + 2.0, 60.0, "2 s of simulated time")
        self.assertFalse(renderer_running(), "a renderer runs although nobody subscribes to a camera")
        # advertised all the same (by /gazebo, as gzserver does): rostopic echo/hz can subscribe
        for topic, cls in TOPICS:
            self.assertEqual(rostopic.get_topic_type(topic)[0], cls._type, topic)

    def test_2_subscribed_the_box_is_where_the_camera_info_puts_it(self):
        for topic, cls in TOPICS:
            CameraAuto.subs[topic] = Latest(topic, cls)
        msg = self.subs["/camera/rgb/image_raw"].wait(lambda m: len(red_pixels(m)[0]) > 0)
        self.assertTrue(renderer_running())
        self.assertEqual((msg.width, msg.height, msg.encoding, msg.header.frame_id), (W, H, "rgb8", FRAME))
        info = self.subs["/camera/rgb/camera_info"].wait()
        self.assertAlmostEqual(info.K[0], F, places=3)
        rows, cols = red_pixels(msg)
        # the face at x = 1.8 spans 0.4 m: F * 0.4 / 1.8 px, centred on the principal point
        size = F * 2 * HALF / FACE
        rospy.loginfo("red box: %d px, columns %d..%d, rows %d..%d (predicted %.1f px wide)",
                      len(rows), cols.min(), cols.max(), rows.min(), rows.max(), size)
        self.assertAlmostEqual(cols.max() - cols.min() + 1, size, delta=3)
        self.assertAlmostEqual(rows.max() - rows.min() + 1, size, delta=3)
        # the box's middle on the principal point of the CameraInfo ((W + 1) / 2, (H + 1) / 2)
        self.assertAlmostEqual(cols.mean(), info.K[2], delta=0.75)
        self.assertAlmostEqual(rows.mean(), info.K[5], delta=0.75)

    def test_3_depth_image_reads_the_face_distance(self):
        centre = (H // 2, W // 2)
        d = self.subs["/camera/depth/image_raw"].wait(lambda m: np.isfinite(depth_array(m)[centre]))
        self.assertEqual((d.width, d.height, d.encoding, d.header.frame_id), (W, H, "32FC1", FRAME))
        a = depth_array(d)
        face = a[H // 2 - 10:H // 2 + 10, W // 2 - 10:W // 2 + 10]       # inside the face (~32 px)
        rospy.loginfo("depth on the face: %.4f..%.4f m (expected %.3f)", face.min(), face.max(), FACE)
        self.assertTrue(np.all(np.abs(face - FACE) <= 0.01), "depth on the face %s..%s, not %.3f +- 0.01"
                        % (face.min(), face.max(), FACE))
        self.assertTrue(np.isnan(a[0, 0]), "the sky (nothing drawn) must be NaN beyond the cutoff")
        info = self.subs["/camera/depth/camera_info"].wait()
        self.assertAlmostEqual(info.K[0], F, places=3)
        self.assertEqual(info.header.frame_id, FRAME)

    def test_4_cloud_points_land_on_the_face_and_the_ground(self):
        centre = (H // 2, W // 2)
        msg = self.subs["/camera/depth/points"].wait(lambda m: np.isfinite(cloud_array(m)["z"][centre]))
        c = cloud_array(msg)
        self.assertEqual((msg.width, msg.height, msg.header.frame_id), (W, H, FRAME))
        self.assertEqual([f.name for f in msg.fields], ["x", "y", "z", "rgb"])
        self.assertFalse(msg.is_dense)
        face = c[H // 2 - 10:H // 2 + 10, W // 2 - 10:W // 2 + 10]
        wx, wy, wz = to_world(face["x"], face["y"], face["z"])
        self.assertTrue(np.all(np.abs(wx - FACE) <= 0.01),
                        "cloud x on the face %s..%s" % (wx.min(), wx.max()))
        self.assertTrue(np.all(np.abs(wy) <= HALF + 0.01) and np.all(np.abs(wz - CAMERA_Z) <= HALF + 0.01))
        # the centre pixel's point: where the pinhole model puts the pixel on the face
        v, u = centre
        p = c[v, u]
        self.assertAlmostEqual(float(p["x"]), (u - CX) * FACE / F, delta=0.01)
        self.assertAlmostEqual(float(p["y"]), (v - CY) * FACE / F, delta=0.01)
        red = (int(p["rgb"]) >> 16) & 255, (int(p["rgb"]) >> 8) & 255, int(p["rgb"]) & 255
        self.assertTrue(red[0] > 100 and red[1] < 60 and red[2] < 60,
                        "the face's points are red: %s" % (red,))
        # the bottom rows see the ground: world height 0
        ground = c[H - 3:, :]
        g = ground["z"][np.isfinite(ground["z"])]
        self.assertGreater(g.size, W, "the bottom rows should see the ground plane")
        _wx, _wy, gz = to_world(ground["x"], ground["y"], ground["z"])
        gz = gz[np.isfinite(gz)]
        rospy.loginfo("ground points: height %.4f..%.4f m", gz.min(), gz.max())
        self.assertTrue(np.all(np.abs(gz) <= 0.01),
                        "ground points at %s..%s, not 0 +- 0.01" % (gz.min(), gz.max()))

    def test_5a_stereo_pair_as_gazebo_plugins(self):
        # the pair straddles the box: left camera 0.035 m left of it, right one 0.035 m right
        shift = F * 0.035 / FACE
        cols = {}
        for side, sign in (("left", 1), ("right", -1)):
            msg = self.subs["/stereo/%s/image_raw" % side].wait(lambda m: len(red_pixels(m)[0]) > 0)
            self.assertEqual((msg.width, msg.height, msg.encoding, msg.header.frame_id),
                             (W, H, "rgb8", "stereo_optical_frame"))
            info = self.subs["/stereo/%s/camera_info" % side].wait()
            cols[side] = red_pixels(msg)[1].mean()
            rospy.loginfo("stereo %s: box middle at column %.2f (cx %.2f)", side, cols[side], info.K[2])
            self.assertAlmostEqual(cols[side], info.K[2] + sign * shift, delta=0.75)
            # P[3] = -fx * baseline on the right camera only
            self.assertAlmostEqual(info.P[3], 0.0 if side == "left" else -F * 0.07, places=6)
        self.assertAlmostEqual(cols["left"] - cols["right"], F * 0.07 / FACE, delta=0.75)

    def test_5b_triggered_camera_one_frame_per_trigger(self):
        trig = self.subs["/trig/image_raw"]
        left = self.subs["/stereo/left/image_raw"]
        self.assertEqual(trig.count, 0, "a triggered camera published without a trigger")
        pub = rospy.Publisher("/trig/image_trigger", Empty, queue_size=10)
        wait_for(lambda: pub.get_num_connections() > 0, 30.0, "/gazebo subscribed to /trig/image_trigger")
        for _ in range(3):
            pub.publish(Empty())
        wait_for(lambda: trig.count >= 3, 60.0, "3 images for 3 triggers")
        seen = left.count
        wait_for(lambda: left.count >= seen + 5, 30.0, "5 more frames of the stereo camera")
        self.assertEqual(trig.count, 3, "more images than triggers")
        msg = trig.msg
        self.assertEqual((msg.width, msg.height, msg.encoding, msg.step, msg.header.frame_id),
                         (W, H, "mono16", 2 * W, "trig_optical_frame"))
        a = np.frombuffer(msg.data, "<u2").reshape(H, W)
        # 16-bit grey of the scene: the red box is darker than the sky behind it
        self.assertLess(int(a[H // 2, W // 2]), 100 * 257)
        self.assertGreater(int(a[5, 5]), 150 * 257)

    def test_5c_lens_distortion_drawn_and_in_d(self):
        import cv2
        msg = self.subs["/lens/image_raw"].wait()
        info = self.subs["/lens/camera_info"].wait()
        self.assertEqual((msg.encoding, msg.step), ("bayer_rggb8", W))
        self.assertEqual(list(info.D), [-0.3, 0.0, 0.0, 0.0, 0.0])        # autoDistortion: the lens
        a = np.frombuffer(msg.data, np.uint8).reshape(H, W)

        def horizon(img, col):
            """First row from the top that sees the ground (240 grey; the sky is 178, no lens black)."""
            return int(np.argmax(img[:, col] > 210))
        # pitched 0.35 rad down: the horizon 0.365 focal lengths above the centre, bent by the barrel
        bent = [horizon(a, c) for c in (15, W // 2, W - 16)]
        K = np.array(info.K).reshape(3, 3)
        straight = [horizon(cv2.undistort(a, K, np.array(info.D)), c) for c in (15, W // 2, W - 16)]
        rospy.loginfo("horizon rows at columns 15, %d, %d: %s; undistorted with D: %s",
                      W // 2, W - 16, bent, straight)
        self.assertGreaterEqual(min(bent[0], bent[2]) - bent[1], 3, "the lens bends the horizon")
        self.assertLessEqual(max(straight) - min(straight), 1, "undistorted with D it is straight")
        # the ground plane's far edge is a little below the horizon at infinity (row cy - F tan 0.35)
        self.assertTrue(0 <= straight[1] - (info.K[5] - F * math.tan(0.35)) <= 3, straight)

    def test_6_renderer_stops_after_the_last_subscriber_left(self):
        self.assertTrue(self.subs, "test_2 subscribed nothing")
        for latest in self.subs.values():
            latest.sub.unregister()
        wait_for(lambda: not renderer_running(), 30.0, "renderer stopped after the last subscriber left")


if __name__ == "__main__":
    rospy.init_node("check_camera_auto")
    rostest.rosrun("modrob_viz", "camera_auto", CameraAuto)
