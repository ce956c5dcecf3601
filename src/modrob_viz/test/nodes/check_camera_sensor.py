#!/usr/bin/env python3
"""rostest: the camera sensor of test/fixtures/camera_box.world (camera at (0,0,1) looking along
+x, hfov 1.0 rad, 320x240; red box of 0.2 m centred at (2,0,1)) seen through camera_renderer."""
import math
import subprocess
import time
import unittest

import cv2
import numpy as np
import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import TransformStamped
from rosgraph_msgs.msg import Log
from sensor_msgs.msg import CameraInfo, Image
from std_msgs.msg import Float64
from std_srvs.srv import Trigger

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


LOG = []


def wait_image(predicate, timeout=60.0, topic=IMAGE):
    last = None
    end = time.monotonic() + timeout
    while time.monotonic() < end and not rospy.is_shutdown():
        try:
            msg = rospy.wait_for_message(topic, Image, timeout=10.0)
        except rospy.ROSException:
            continue
        last = msg
        if predicate(msg):
            return msg
    return last


def logged(text):
    return [m for m in LOG if text in m]


class CameraSensor(unittest.TestCase):
    def test_1_pinhole_zoom_and_camera_info(self):
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

    def test_2_zero_size_camera_info_and_missing_frame(self):
        # the camera post's optical frame at the sensor: a second view of the box
        static = tf2_ros.StaticTransformBroadcaster()
        info_pub = rospy.Publisher("/late_info/camera_info", CameraInfo, queue_size=1, latch=True)
        bad = CameraInfo()
        bad.header.frame_id = "camera_post_view"
        info_pub.publish(bad)                  # width = height = 0
        t = TransformStamped()
        t.header.frame_id = "gazebo/camera_post/camera_link/camera1"
        t.child_frame_id = "camera_post_view"
        t.transform.rotation.w = 1.0
        static.sendTransform(t)
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline and not (logged("unusable CameraInfo") and logged("no_such_frame")):
            time.sleep(0.2)
        self.assertTrue(logged("unusable CameraInfo on /late_info/camera_info"),
                        "no message for the zero-size CameraInfo; log: %s" % LOG[-10:])
        self.assertTrue(logged("frame 'no_such_frame' is not in tf"), "no message for the missing frame")
        self.assertIsNotNone(wait_image(lambda m: True, 20.0), "the sensor stream stopped")
        good = CameraInfo()
        good.header.frame_id = "camera_post_view"
        good.width, good.height = 160, 120
        good.K = [150.0, 0, 80, 0, 150.0, 60, 0, 0, 1]
        good.P = [150.0, 0, 80, 0, 0, 150.0, 60, 0, 0, 0, 1, 0]
        info_pub.publish(good)
        late = wait_image(lambda m: red_box(m) is not None, 40.0, "/late_info/image")
        self.assertIsNotNone(late and red_box(late), "the camera with a now valid CameraInfo shows no box")
        box = red_box(late)
        self.assertLess(abs(box["u"] - 80), 3.0)
        static.sendTransform([t, _frame("gazebo/camera_post/camera_link/camera1", "no_such_frame")])
        self.assertIsNotNone(wait_image(lambda m: red_box(m) is not None, 40.0, "/no_frame/image"),
                             "the camera whose frame appeared renders nothing")
        self.assertEqual(len(logged("frame 'no_such_frame' is not in tf")), 1, "the message must come once")

    def test_3_frames_and_video_saved_by_services(self):
        for srv in ("save_frame", "start_recording", "stop_recording"):
            rospy.wait_for_service("/camera_renderer/" + srv, 30.0)
        saved = rospy.ServiceProxy("/camera_renderer/save_frame", Trigger)()
        self.assertTrue(saved.success, saved.message)
        png = [p for p in saved.message.split() if p.endswith(".png") and "test_cam" in p]
        self.assertTrue(png, "no test_cam frame in %r" % saved.message)
        img = cv2.imread(png[0])
        self.assertEqual(img.shape[:2], (H, W))
        started = rospy.ServiceProxy("/camera_renderer/start_recording", Trigger)()
        self.assertTrue(started.success, started.message)
        count = 0
        end = time.monotonic() + 30
        while count < 10 and time.monotonic() < end:
            rospy.wait_for_message(IMAGE, Image, timeout=10.0)
            count += 1
        stopped = rospy.ServiceProxy("/camera_renderer/stop_recording", Trigger)()
        self.assertTrue(stopped.success, stopped.message)
        video = [p for p in started.message.split() if "test_cam" in p][0]
        cap = cv2.VideoCapture(video)
        frames = 0
        while cap.read()[0]:
            frames += 1
        self.assertGreaterEqual(frames, 5, "%s holds %d frames" % (video, frames))

    def test_4_simulator_restart(self):
        before = rospy.wait_for_message(IMAGE, Image, timeout=30.0).header.stamp
        subprocess.check_call(["rosnode", "kill", "/gazebo"], stdout=subprocess.DEVNULL)
        # The new simulator runs at a fifth of real time: after the clock goes back the renderer
        # resets RViz, and the box is drawn again with the simulator's next send of the scene
        # markers (every 2 s of wall time); all that must happen before the new sim time passes
        # ``before`` (~4 s after the first start), also on a loaded machine.
        gz = subprocess.Popen(["rosrun", "modrob_sim", "gazebo", "__name:=gazebo", "_real_time_factor:=0.2"])
        try:
            after = wait_image(lambda m: m.header.stamp < before and red_box(m) is not None, 90.0)
            self.assertIsNotNone(after, "no image after the restart")
            self.assertLess(after.header.stamp, before, "images are not stamped with the new sim time")
            self.assertIsNotNone(red_box(after), "the restarted scene shows no box")
        finally:
            gz.terminate()
            gz.wait(20)


def _frame(parent, child):
    t = TransformStamped()
    t.header.frame_id, t.child_frame_id = parent, child
    t.transform.rotation.w = 1.0
    return t


if __name__ == "__main__":
    rospy.init_node("check_camera_sensor")
    rospy.Subscriber("/rosout", Log, lambda m: LOG.append(m.msg), queue_size=100)
    rostest.rosrun("modrob_viz", "check_camera_sensor", CameraSensor)
