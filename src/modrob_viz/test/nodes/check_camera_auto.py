#!/usr/bin/env python3
"""rostest camera_auto.test: the simulator runs the camera renderer only while a camera is
subscribed, a depth camera's outputs are exact to the geometry, gazebo_plugins' other cameras
(stereo pair, triggered, lens distortion, 16-bit and bayer formats: fixtures/camera_family.urdf)
publish as theirs do, and <clip> is applied (fixtures/camera_clip.world).

A depth camera (libgazebo_ros_openni_kinect.so, TurtleBot3 waffle's topic names) 0.5 m up at the
origin of its post, looking along the post's +x (hfov 1.0 rad, 160x120); a red box of 0.4 m
centred 2 m ahead at 0.5 m: its face is 1.8 m ahead (the posts are turned by pi in the world,
looking along -x, away from camera_clip.world's boxes). The tests run in name order on one
simulator and one renderer start (a renderer's start-up is most of a camera test's time)."""
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

from modrob_sim import waits
from modrob_sim.waits import wait_until

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
          ("/trig/image_raw", Image), ("/lens/image_raw", Image), ("/lens/camera_info", CameraInfo),
          ("/wide_cam/image_raw", Image), ("/clip_cam/image_raw", Image))


def renderer_running():
    """The renderer node is registered and answers (a stopped one may leave its registration)."""
    try:
        uri = rosgraph.Master("/check_camera_auto").lookupNode(RENDERER)
        ServerProxy(uri).getPid("/check_camera_auto")
        return True
    except (rosgraph.MasterError, OSError):
        return False


class Latest(waits.Latest):
    """waits.Latest of a camera topic: the newest ``queue_size`` queued, room for a whole image,
    and waits of up to 90 s (the renderer starts with the first subscription)."""

    def __init__(self, topic, cls, queue_size=1):
        waits.Latest.__init__(self, topic, cls, queue_size=queue_size, buff_size=2 ** 24)

    def wait(self, cond=lambda m: True, timeout=90.0, what="a suitable message"):
        return waits.Latest.wait(self, cond, timeout, what)


def red_pixels(msg):
    a = np.frombuffer(msg.data, np.uint8).reshape(msg.height, msg.width, 3).astype(int)
    return np.nonzero((a[..., 0] > 100) & (a[..., 1] < 60) & (a[..., 2] < 60))


def depth_array(msg):
    return np.frombuffer(msg.data, "<f4").reshape(msg.height, msg.width)


def cloud_array(msg):
    dt = np.dtype({"names": ["x", "y", "z", "rgb"], "formats": ["<f4", "<f4", "<f4", "<u4"],
                   "offsets": [0, 4, 8, 16], "itemsize": msg.point_step})
    return np.frombuffer(msg.data, dt).reshape(msg.height, msg.width)


def to_post(x, y, z):
    """The depth camera's optical frame (z forward, x right, y down) in its post's frame (x forward,
    y left, z up; origin on the ground)."""
    return z, -x, CAMERA_Z - y


# camera_clip.world: wide_cam and clip_cam at (0, 0, 1) look along +x (hfov 1.0 rad, 320x240);
# box: (colour channel, centre ahead x, sideways y, height above the camera z, half edge)
CLIP_W, CLIP_H = 320, 240
CLIP_F = CLIP_W / (2.0 * math.tan(HFOV / 2.0))
BOXES = {"green": (1, 0.3, 0.06, 0.04, 0.03), "red": (0, 2.0, 0.0, 0.0, 0.1),
         "blue": (2, 4.0, -0.8, -0.2, 0.15)}


def clip_pixels(msg, colour):
    """(rows, columns) of the pixels of a saturated colour (the others dark)."""
    a = np.frombuffer(msg.data, np.uint8).reshape(msg.height, msg.width, 3).astype(int)
    ch = BOXES[colour][0]
    others = [c for c in range(3) if c != ch]
    return np.nonzero((a[..., ch] > 100) & (a[..., others[0]] < 60) & (a[..., others[1]] < 60))


def clip_predicted_uv(colour):
    """Pixel of the centre of the box's face towards the camera (pinhole, Gazebo's cx, cy)."""
    _, x, y, z, half = BOXES[colour]
    return (CLIP_W + 1) / 2.0 - CLIP_F * y / (x - half), (CLIP_H + 1) / 2.0 - CLIP_F * z / (x - half)


def clip_seen(msg):
    return {c: len(clip_pixels(msg, c)[1]) for c in BOXES}


def wait_image(topic, predicate, timeout=60.0):
    """The first image on ``topic`` that satisfies ``predicate`` (or the last one seen)."""
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


class CameraAuto(unittest.TestCase):
    subs = {}

    def test_1_nothing_runs_while_unsubscribed(self):
        # the box and the camera spawned, and 2 s of simulated time with nobody subscribed
        wait_until(lambda: rospy.get_param("/gazebo/camera_sensors", {}), 60.0, "camera sensor registered")
        t0 = rospy.wait_for_message("/clock", Clock, 30.0).clock.to_sec()
        wait_until(lambda: rospy.get_time() > t0 + 2.0, 60.0, "2 s of simulated time")
        self.assertFalse(renderer_running(), "a renderer runs although nobody subscribes to a camera")
        # advertised all the same (by /gazebo, as gzserver does): rostopic echo/hz can subscribe
        for topic, cls in TOPICS:
            self.assertEqual(rostopic.get_topic_type(topic)[0], cls._type, topic)

    def test_2_subscribed_the_box_is_where_the_camera_info_puts_it(self):
        for topic, cls in TOPICS:
            # every image of the triggered camera counts: a queue for the three that come together
            CameraAuto.subs[topic] = Latest(topic, cls, 10 if topic == "/trig/image_raw" else 1)
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
        wx, wy, wz = to_post(face["x"], face["y"], face["z"])
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
        _wx, _wy, gz = to_post(ground["x"], ground["y"], ground["z"])
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
        wait_until(lambda: pub.get_num_connections() > 0, 30.0, "/gazebo subscribed to /trig/image_trigger")
        for _ in range(3):
            pub.publish(Empty())
        wait_until(lambda: trig.count >= 3, 60.0, "3 images for 3 triggers (%d came)" % trig.count)
        seen = left.count
        wait_until(lambda: left.count >= seen + 5, 30.0, "5 more frames of the stereo camera")
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

    def test_5d_wide_clip_camera_sees_all_three_boxes(self):
        msg = wait_image("/wide_cam/image_raw", lambda m: min(clip_seen(m).values()) >= 20)
        self.assertIsNotNone(msg, "no image on /wide_cam/image_raw")
        counts = clip_seen(msg)
        rospy.loginfo("wide_cam: pixels per box %s", counts)
        for colour in BOXES:
            self.assertGreaterEqual(counts[colour], 20, "wide_cam does not show the %s box" % colour)
            rows, cols = clip_pixels(msg, colour)
            u, v = (cols.min() + cols.max() + 1) / 2.0, (rows.min() + rows.max() + 1) / 2.0
            pu, pv = clip_predicted_uv(colour)
            self.assertLess(abs(u - pu), 6.0, "%s box at column %.1f, pinhole model %.1f" % (colour, u, pu))
            self.assertLess(abs(v - pv), 6.0, "%s box at row %.1f, pinhole model %.1f" % (colour, v, pv))

    def test_5e_clip_camera_drops_boxes_outside_near_far(self):
        def only_red(m):
            c = clip_seen(m)
            return c["red"] >= 20 and c["green"] == 0 and c["blue"] == 0
        msg = wait_image("/clip_cam/image_raw", only_red)
        self.assertIsNotNone(msg, "no image on /clip_cam/image_raw")
        counts = clip_seen(msg)
        rospy.loginfo("clip_cam: pixels per box %s", counts)
        self.assertGreaterEqual(counts["red"], 20, "the red box (2 m, inside near 0.5 .. far 3) is missing")
        self.assertEqual(counts["green"], 0, "the green box 0.3 m ahead is nearer than near = 0.5 m "
                                             "but drawn")
        self.assertEqual(counts["blue"], 0, "the blue box 4 m ahead is beyond far = 3 m but drawn")

    def test_6_renderer_stops_after_the_last_subscriber_left(self):
        self.assertTrue(self.subs, "test_2 subscribed nothing")
        for latest in self.subs.values():
            latest.sub.unregister()
        wait_until(lambda: not renderer_running(), 30.0, "renderer stopped after the last subscriber left")


if __name__ == "__main__":
    rospy.init_node("check_camera_auto")
    rostest.rosrun("modrob_viz", "camera_auto", CameraAuto)
